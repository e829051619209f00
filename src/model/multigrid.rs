//! The wind's pressure solve by geometric multigrid (ours; docs/method.md
//! section 3): V-cycles with a red-black Gauss-Seidel smoother, the CPU
//! reference of glsl/wind/mg_*.comp, kernel by kernel.
//!
//! The Poisson equation of the projection, sum over free faces of
//! (p_nb - p) / h^2 = div, is solved in its integrated (finite-volume) form:
//! each face has a conductance K = area / distance between the two pressure
//! samples, and for every cell
//!
//!   sum_f K_f (p - p_nb) = b,   b = -div * cell volume,
//!
//! with p_nb = 0 beyond an open side (Dirichlet) and K = 0 across a wall,
//! a solid or an inflow face (Neumann). This is the Jacobi solver's
//! equation multiplied by the cell volume, so both solvers have the same
//! solution and the same projection.
//!
//! Coarsening halves the axes whose spacing is within 1.5x of the finest
//! (semi-coarsening of flat cells; an odd count leaves its last coarse cell
//! one fine cell thick). A coarse face's conductance is the sum of the fine
//! faces it covers divided by how much longer the distance between
//! pressure samples became (2 along a halved axis): areas add, distances
//! double. The correction comes back by trilinear interpolation (an open
//! side interpolates towards zero outside, a closed one mirrors), and a
//! coarse cell's right-hand side gathers its fine cells' residuals by the
//! transpose of that interpolation. The coarsest level (at most
//! `MAX_COARSEST_CELLS` cells) is smoothed `COARSEST_SWEEPS` times. The GPU
//! runs each V-cycle's coarse levels, from `tail_level` down and back up,
//! in one workgroup, and the finer ones kernel by kernel.

use glam::{UVec3, Vec3};

/// Red-black Gauss-Seidel sweeps before restricting and after prolonging
/// (the GPU's tail kernel reads the same constants).
pub const PRE_SMOOTH: u32 = crate::interface::MG_PRE_SMOOTH;
pub const POST_SMOOTH: u32 = crate::interface::MG_POST_SMOOTH;
/// Coarsening stops at this many cells (4 x 2 x 4 on the paper's grid).
/// With the sides along an inflow closed, the pressure's slowest mode is a
/// ramp from the inflow to the one open side, which Gauss-Seidel on the
/// coarsest level barely moves on 8 x 3 x 8 cells (at 512 cells table1 kept
/// 45% of its divergence); on 4 x 2 x 4 it converges in the sweeps below.
pub const MAX_COARSEST_CELLS: u32 = 64;
/// Sweeps on the coarsest level. (More made no step better and some worse:
/// the coarse operator only approximates the fine one near obstacles.)
pub const COARSEST_SWEEPS: u32 = 40;
/// The most V-cycles a step runs by default. Seven from zero pressure
/// left at most 0.4% of the divergence in the first ten steps of every
/// shipped scene (six left up to 0.9%; docs/physics.md); with the
/// tolerance below most steps stop after one or two.
pub const DEFAULT_V_CYCLES: u32 = 7;
/// The share of a step's rms divergence the solve may leave by default
/// (`Multigrid::solve`). With it, on 120 steps of eight shipped scenes,
/// no scene's worst step leaves more than seven cycles from zero left,
/// and the median step runs two to four cycles (1e-3 would let hills'
/// worst step leave 5x more; docs/physics.md).
pub const DEFAULT_PRESSURE_TOLERANCE: f32 = 1e-4;

/// Where a pressure solve starts (`Multigrid::solve`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Start {
    /// Zero pressure: the residual is the right-hand side.
    #[default]
    Zero,
    /// The last step's pressure.
    Last,
    /// The last two steps' pressures carried on in time, 2 p_n - p_(n-1).
    Extrapolated,
}

/// What one pressure solve did (`Multigrid::solve`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Solve {
    /// V-cycles run.
    pub v_cycles: u32,
    pub start: Start,
    /// The rms residual left over the right-hand side's: the share of
    /// the divergence the projection leaves (0 when there was none).
    pub share_left: f32,
}

/// The multigrid's pressure solves over a run (the GPU's `WindPass::read_solve_counts`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SolveCounts {
    /// Steps solved.
    pub steps: u32,
    /// V-cycles per step: median, most and mean.
    pub v_cycles_median: u32,
    pub v_cycles_most: u32,
    pub v_cycles_mean: f32,
    /// Dispatches of a step that run workgroups, at the median V-cycles.
    pub dispatches_median: u32,
    /// Dispatches a step records, those of V-cycles switched off on zero
    /// workgroups included.
    pub dispatches_recorded: u32,
}

/// One level of the hierarchy. Level 0 is the wind grid itself.
#[derive(Clone, Debug, PartialEq)]
pub struct Level {
    pub cells: UVec3,
    /// Fine cells per coarse cell along each axis, towards the next
    /// coarser level (1 or 2; unused on the coarsest).
    pub ratio: UVec3,
    /// Conductance of every face, per axis, in the velocity's face layout
    /// (`cells` plus one along the face's own axis).
    pub conductance: [Vec<f32>; 3],
}

impl Level {
    pub fn cell_count(&self) -> usize {
        (self.cells.x * self.cells.y * self.cells.z) as usize
    }

    pub fn face_dims(&self, axis: usize) -> UVec3 {
        let mut d = self.cells;
        d[axis] += 1;
        d
    }

    pub fn face_index(&self, axis: usize, f: UVec3) -> usize {
        let d = self.face_dims(axis);
        (f.x + d.x * (f.y + d.y * f.z)) as usize
    }

    pub fn cell_index(&self, c: UVec3) -> usize {
        (c.x + self.cells.x * (c.y + self.cells.y * c.z)) as usize
    }

    fn cell_of(&self, index: usize) -> UVec3 {
        let n = self.cells;
        let i = index as u32;
        UVec3::new(i % n.x, (i / n.x) % n.y, i / (n.x * n.y))
    }

    /// The 6-point stencil at cell `c`: (sum of K, sum of K * p_nb).
    fn stencil(&self, p: &[f32], c: UVec3) -> (f32, f32) {
        let (diagonal, terms) = self.stencil_terms(c);
        let mut neighbours = 0.0;
        for (nb, k) in terms {
            neighbours += k * p[nb];
        }
        (diagonal, neighbours)
    }

    /// The stencil's terms at cell `c`: the sum of K over its conducting
    /// faces, and (neighbour cell, K) for those with a cell beyond (an
    /// open side's outside pressure is zero), axis by axis, low side
    /// first.
    fn stencil_terms(&self, c: UVec3) -> (f32, Vec<(usize, f32)>) {
        let mut diagonal = 0.0;
        let mut terms = Vec::with_capacity(6);
        for axis in 0..3 {
            for side in 0..2u32 {
                let mut f = c;
                f[axis] += side;
                let k = self.conductance[axis][self.face_index(axis, f)];
                if k == 0.0 {
                    continue;
                }
                diagonal += k;
                let mut nb = c.as_ivec3();
                nb[axis] += if side == 1 { 1 } else { -1 };
                let inside = nb[axis] >= 0 && nb[axis] < self.cells[axis] as i32;
                if inside {
                    terms.push((self.cell_index(nb.as_uvec3()), k));
                }
            }
        }
        (diagonal, terms)
    }

    /// One red-black Gauss-Seidel half-sweep: the cells whose i + j + k has
    /// parity `color` take the value that zeroes their residual. Cells of
    /// one colour only neighbour the other colour, so the order within a
    /// half-sweep does not matter (and the GPU runs it in parallel).
    pub fn smooth(&self, p: &mut [f32], b: &[f32], color: u32) {
        for index in 0..self.cell_count() {
            let c = self.cell_of(index);
            if (c.x + c.y + c.z) % 2 != color {
                continue;
            }
            let (diagonal, neighbours) = self.stencil(p, c);
            p[index] = if diagonal == 0.0 {
                0.0
            } else {
                (b[index] + neighbours) / diagonal
            };
        }
    }

    /// b - A p at cell `index`.
    pub fn residual(&self, p: &[f32], b: &[f32], index: usize) -> f32 {
        let (diagonal, neighbours) = self.stencil(p, self.cell_of(index));
        b[index] - (diagonal * p[index] - neighbours)
    }

    /// The weight of coarse cell `c` (of level `coarse`) in fine cell `f`'s
    /// interpolation: the product of the axes' weights.
    fn weight(&self, coarse: &Level, f: UVec3, c: UVec3) -> f32 {
        let parent = f / self.ratio;
        (0..3)
            .map(|a| {
                // The side of the grid beyond f's parent on f's side, if any:
                // open when the parent's face there conducts.
                let (centre, _) = coarse_span(parent[a], self.ratio[a], self.cells[a]);
                let mut side = parent;
                side[a] = if (f[a] as f32 + 0.5) < centre {
                    0
                } else {
                    coarse.cells[a]
                };
                let open = coarse.conductance[a][coarse.face_index(a, side)] > 0.0;
                axis_weight(f[a], c[a], self.ratio[a], self.cells[a], open)
            })
            .product()
    }

    /// The coarse cells (index, weight) that fine cell `f` interpolates:
    /// its parent and, along each halved axis, the neighbour on its side.
    fn interpolation<'a>(
        &'a self,
        coarse: &'a Level,
        f: UVec3,
    ) -> impl Iterator<Item = (usize, f32)> + 'a {
        let parent = f / self.ratio;
        let lo = parent.saturating_sub(UVec3::ONE);
        let hi = (parent + 1).min(coarse.cells - 1);
        candidates(lo, hi).filter_map(move |c| {
            let w = self.weight(coarse, f, c);
            (w != 0.0).then(|| (coarse.cell_index(c), w))
        })
    }

    /// The fine cells (index, weight) whose interpolation reaches coarse
    /// cell `c`: the transpose of `interpolation`.
    fn gather<'a>(
        &'a self,
        coarse: &'a Level,
        c: UVec3,
    ) -> impl Iterator<Item = (usize, f32)> + 'a {
        let r = self.ratio;
        let lo = (c * r).saturating_sub(r - 1);
        let hi = (c * r + r + (r - 1)).min(self.cells) - 1;
        candidates(lo, hi).filter_map(move |f| {
            let w = self.weight(coarse, f, c);
            (w != 0.0).then(|| (self.cell_index(f), w))
        })
    }
}

/// Every lattice point from `lo` to `hi`, inclusive, x fastest.
fn candidates(lo: UVec3, hi: UVec3) -> impl Iterator<Item = UVec3> {
    (lo.z..=hi.z).flat_map(move |z| {
        (lo.y..=hi.y).flat_map(move |y| (lo.x..=hi.x).map(move |x| UVec3::new(x, y, z)))
    })
}

/// The level hierarchy, built once per wind grid.
#[derive(Clone, Debug, Default)]
pub struct Multigrid {
    pub levels: Vec<Level>,
    /// What a V-cycle applies at each level, worked out from `levels`
    /// once, at the first CPU solve (`Operators`): the GPU's wind pass
    /// makes a `WindField` for its initial state and reads only the
    /// levels (working the lists out was about 0.2 s of every render's
    /// start on a 60 x 20 x 60 grid).
    operators: std::sync::OnceLock<Vec<Operators>>,
}

/// The operators are a function of the levels: two hierarchies are equal
/// when their levels are, whether or not either has worked them out.
impl PartialEq for Multigrid {
    fn eq(&self, other: &Self) -> bool {
        self.levels == other.levels
    }
}

/// Level `l`'s stencil and its transfers to level `l + 1`, as lists:
/// the same terms in the same order as `Level::stencil`, `interpolation`
/// and `gather` sum them, so a V-cycle gives the same bits as by those
/// definitions (a test below holds it), without working every weight out
/// again at every cell of every cycle (which cost the CPU reference
/// three quarters of a turbulent trace's time).
#[derive(Clone, Debug, Default, PartialEq)]
struct Operators {
    /// Each cell's sum of K.
    diagonal: Vec<f32>,
    /// Each cell's neighbours inside the grid across a conducting face,
    /// (cell, K): cell c's are `neighbours[starts[c]..starts[c + 1]]`.
    neighbours: Lists,
    /// Each fine cell's coarse cells (index, weight); empty on the
    /// coarsest level.
    interpolation: Lists,
    /// Each coarse cell's fine cells (index, weight), the transpose.
    gather: Lists,
}

/// Lists of (index, weight) end to end: list i is
/// `entries[starts[i]..starts[i + 1]]`.
#[derive(Clone, Debug, Default, PartialEq)]
struct Lists {
    starts: Vec<u32>,
    entries: Vec<(u32, f32)>,
}

impl Lists {
    fn of(count: usize, mut list: impl FnMut(usize) -> Vec<(usize, f32)>) -> Self {
        let mut lists = Lists {
            starts: Vec::with_capacity(count + 1),
            entries: Vec::new(),
        };
        lists.starts.push(0);
        for i in 0..count {
            lists
                .entries
                .extend(list(i).into_iter().map(|(j, w)| (j as u32, w)));
            lists.starts.push(lists.entries.len() as u32);
        }
        lists
    }

    fn get(&self, i: usize) -> &[(u32, f32)] {
        &self.entries[self.starts[i] as usize..self.starts[i + 1] as usize]
    }
}

impl Operators {
    fn of(level: &Level, coarse: Option<&Level>) -> Self {
        let cells = level.cell_count();
        let mut diagonal = Vec::with_capacity(cells);
        let neighbours = Lists::of(cells, |i| {
            let (sum, terms) = level.stencil_terms(level.cell_of(i));
            diagonal.push(sum);
            terms
        });
        let (interpolation, gather) = match coarse {
            Some(coarse) => (
                Lists::of(cells, |i| {
                    level.interpolation(coarse, level.cell_of(i)).collect()
                }),
                Lists::of(coarse.cell_count(), |i| {
                    level.gather(coarse, coarse.cell_of(i)).collect()
                }),
            ),
            None => Default::default(),
        };
        Self {
            diagonal,
            neighbours,
            interpolation,
            gather,
        }
    }

    /// `Level::stencil` from the lists.
    fn stencil(&self, p: &[f32], index: usize) -> (f32, f32) {
        let mut neighbours = 0.0;
        for &(nb, k) in self.neighbours.get(index) {
            neighbours += k * p[nb as usize];
        }
        (self.diagonal[index], neighbours)
    }

    /// `Level::smooth` from the lists.
    fn smooth(&self, level: &Level, p: &mut [f32], b: &[f32], color: u32) {
        let n = level.cells;
        let mut index = 0;
        for z in 0..n.z {
            for y in 0..n.y {
                for x in 0..n.x {
                    if (x + y + z) % 2 == color {
                        let (diagonal, neighbours) = self.stencil(p, index);
                        p[index] = if diagonal == 0.0 {
                            0.0
                        } else {
                            (b[index] + neighbours) / diagonal
                        };
                    }
                    index += 1;
                }
            }
        }
    }

    /// `Level::residual` from the lists.
    fn residual(&self, p: &[f32], b: &[f32], index: usize) -> f32 {
        let (diagonal, neighbours) = self.stencil(p, index);
        b[index] - (diagonal * p[index] - neighbours)
    }
}

impl Multigrid {
    /// Level 0 from the wind grid's faces: K = area / h for a free face,
    /// 0 for any other; then coarser levels until one has at most
    /// `MAX_COARSEST_CELLS` cells or cannot shrink.
    ///
    /// `cells` and `h` are the wind grid's cells and cell size; `free[axis]`
    /// says for each face, in the velocity's layout, whether air may cross it.
    pub fn new(cells: UVec3, h: Vec3, free: &[Vec<bool>; 3]) -> Self {
        Self {
            levels: Self::levels_of(cells, h, free),
            operators: std::sync::OnceLock::new(),
        }
    }

    /// Each level's operators (`Operators`), worked out on first use.
    fn operators(&self) -> &[Operators] {
        self.operators.get_or_init(|| {
            (0..self.levels.len())
                .map(|l| Operators::of(&self.levels[l], self.levels.get(l + 1)))
                .collect()
        })
    }

    /// The hierarchy's levels alone, without the CPU's operators: what
    /// the GPU's kernels read (a moved wind window's, rebuilt at each
    /// move, costs a tenth of `new`).
    pub fn levels_of(cells: UVec3, h: Vec3, free: &[Vec<bool>; 3]) -> Vec<Level> {
        let conductance = std::array::from_fn(|axis| {
            let area_over_distance = h.x * h.y * h.z / (h[axis] * h[axis]);
            free[axis]
                .iter()
                .map(|&free| if free { area_over_distance } else { 0.0 })
                .collect()
        });
        let mut spacing = h;
        let mut levels = vec![Level {
            cells,
            ratio: UVec3::ONE,
            conductance,
        }];
        loop {
            let fine = levels.last_mut().expect("level 0 exists");
            if fine.cells.x * fine.cells.y * fine.cells.z <= MAX_COARSEST_CELLS {
                break;
            }
            fine.ratio = coarsening(fine.cells, spacing);
            if fine.ratio == UVec3::ONE {
                break;
            }
            spacing *= fine.ratio.as_vec3();
            let coarse = coarsen(fine);
            levels.push(coarse);
        }
        levels
    }

    /// Level 0's right-hand side: b = -div * cell volume (`h`: cell size).
    pub fn rhs_from_divergence(h: Vec3, divergence: &[f32]) -> Vec<f32> {
        let volume = h.x * h.y * h.z;
        divergence.iter().map(|d| -d * volume).collect()
    }

    /// Sum over level 0's cells of (b - A p)^2.
    pub fn residual_squares(&self, p: &[f32], b: &[f32]) -> f64 {
        let ops = &self.operators()[0];
        (0..b.len())
            .map(|i| (ops.residual(p, b, i) as f64).powi(2))
            .sum()
    }

    /// The pressure solve (issue 63). It starts from whichever of zero,
    /// the last step's pressure `p` and the last two carried on,
    /// 2 p - `before`, leaves the smallest residual (zero's is b); then
    /// runs V-cycles until the rms residual is at most `tolerance` of b's,
    /// at most `max_cycles`. `before` becomes the last step's pressure for
    /// the next solve. In a steady or steadily changing wind one cycle
    /// suffices or none; after a change (the first steps, a collider's
    /// push) the cycles run on, each dividing the residual by 3 to 30,
    /// where a fixed count from the last pressure had left up to 88%
    /// (docs/perf.md).
    pub fn solve(
        &self,
        [p, before]: [&mut [f32]; 2],
        b: &[f32],
        work: &mut Work,
        max_cycles: u32,
        tolerance: f32,
    ) -> Solve {
        let zero: f64 = b.iter().map(|&v| (v as f64).powi(2)).sum();
        let last = self.residual_squares(p, b);
        for (before, &now) in before.iter_mut().zip(p.iter()) {
            *before = 2.0 * now - *before;
        }
        let extrapolated = self.residual_squares(before, b);
        // `before` holds the extrapolation now: swap it in where it
        // wins, so that `before` is the last pressure either way.
        let (start, mut squares) = if extrapolated < last && extrapolated < zero {
            p.swap_with_slice(before);
            (Start::Extrapolated, extrapolated)
        } else {
            before.copy_from_slice(p);
            if last < zero {
                (Start::Last, last)
            } else {
                p.fill(0.0);
                (Start::Zero, zero)
            }
        };
        let goal = (tolerance as f64).powi(2) * zero;
        let mut v_cycles = 0;
        while squares > goal && v_cycles < max_cycles {
            self.v_cycle(p, b, work);
            squares = self.residual_squares(p, b);
            v_cycles += 1;
        }
        Solve {
            v_cycles,
            start,
            share_left: if zero > 0.0 {
                (squares / zero).sqrt() as f32
            } else {
                0.0
            },
        }
    }

    /// One V-cycle on `p` (level 0, improved in place) for right-hand side
    /// `b`. `work` holds the coarse levels' pressure and right-hand side.
    /// By the operators' lists: the same sums as `v_cycle_by_definition`.
    pub fn v_cycle(&self, p: &mut [f32], b: &[f32], work: &mut Work) {
        let last = self.levels.len() - 1;
        work.ensure(self);
        for l in 0..last {
            let (fine_p, coarse_p, fine_b, coarse_b) = work.pair(l, p, b);
            let (level, ops) = (&self.levels[l], &self.operators()[l]);
            for _ in 0..PRE_SMOOTH {
                ops.smooth(level, fine_p, fine_b, 0);
                ops.smooth(level, fine_p, fine_b, 1);
            }
            // Restrict by the transpose of the interpolation: each coarse
            // cell gathers the fine residuals weighted as the interpolation
            // would spread its value (the right-hand side is integrated
            // over the cell, so the weights are not averaged), and its
            // correction starts from zero.
            let residual: Vec<f32> = (0..level.cell_count())
                .map(|f| ops.residual(fine_p, fine_b, f))
                .collect();
            for (index, (cp, cb)) in coarse_p.iter_mut().zip(coarse_b.iter_mut()).enumerate() {
                *cb = ops
                    .gather
                    .get(index)
                    .iter()
                    .map(|&(f, w)| w * residual[f as usize])
                    .sum();
                *cp = 0.0;
            }
        }
        {
            let (coarsest_p, coarsest_b) = work.level(last, p, b);
            let (level, ops) = (&self.levels[last], &self.operators()[last]);
            for _ in 0..COARSEST_SWEEPS {
                ops.smooth(level, coarsest_p, coarsest_b, 0);
                ops.smooth(level, coarsest_p, coarsest_b, 1);
            }
        }
        for l in (0..last).rev() {
            let (fine_p, coarse_p, fine_b, _) = work.pair(l, p, b);
            let (level, ops) = (&self.levels[l], &self.operators()[l]);
            // Prolong: every fine cell adds the trilinear interpolation of
            // the coarse correction at its centre.
            for (index, value) in fine_p.iter_mut().enumerate() {
                *value += ops
                    .interpolation
                    .get(index)
                    .iter()
                    .map(|&(c, w)| w * coarse_p[c as usize])
                    .sum::<f32>();
            }
            for _ in 0..POST_SMOOTH {
                ops.smooth(level, fine_p, fine_b, 0);
                ops.smooth(level, fine_p, fine_b, 1);
            }
        }
    }

    /// `v_cycle` by the definitions: every stencil, weight and transfer
    /// worked out where it is applied (the reference the lists are held
    /// to, bit for bit).
    #[cfg(test)]
    fn v_cycle_by_definition(&self, p: &mut [f32], b: &[f32], work: &mut Work) {
        let last = self.levels.len() - 1;
        work.ensure(self);
        for l in 0..last {
            let (fine_p, coarse_p, fine_b, coarse_b) = work.pair(l, p, b);
            let level = &self.levels[l];
            for _ in 0..PRE_SMOOTH {
                level.smooth(fine_p, fine_b, 0);
                level.smooth(fine_p, fine_b, 1);
            }
            // Restrict by the transpose of the interpolation: each coarse
            // cell gathers the fine residuals weighted as the interpolation
            // would spread its value (the right-hand side is integrated
            // over the cell, so the weights are not averaged), and its
            // correction starts from zero.
            let coarse = &self.levels[l + 1];
            let residual: Vec<f32> = (0..level.cell_count())
                .map(|f| level.residual(fine_p, fine_b, f))
                .collect();
            for (index, (cp, cb)) in coarse_p.iter_mut().zip(coarse_b.iter_mut()).enumerate() {
                *cb = level
                    .gather(coarse, coarse.cell_of(index))
                    .map(|(f, w)| w * residual[f])
                    .sum();
                *cp = 0.0;
            }
        }
        {
            let (coarsest_p, coarsest_b) = work.level(last, p, b);
            for _ in 0..COARSEST_SWEEPS {
                self.levels[last].smooth(coarsest_p, coarsest_b, 0);
                self.levels[last].smooth(coarsest_p, coarsest_b, 1);
            }
        }
        for l in (0..last).rev() {
            let (fine_p, coarse_p, fine_b, _) = work.pair(l, p, b);
            let level = &self.levels[l];
            // Prolong: every fine cell adds the trilinear interpolation of
            // the coarse correction at its centre.
            let coarse = &self.levels[l + 1];
            for (index, value) in fine_p.iter_mut().enumerate() {
                *value += level
                    .interpolation(coarse, level.cell_of(index))
                    .map(|(c, w)| w * coarse_p[c])
                    .sum::<f32>();
            }
            for _ in 0..POST_SMOOTH {
                level.smooth(fine_p, fine_b, 0);
                level.smooth(fine_p, fine_b, 1);
            }
        }
    }

    /// Cells of every level after the first: the coarse levels' storage.
    pub fn coarse_cell_count(&self) -> usize {
        self.levels[1..].iter().map(Level::cell_count).sum()
    }

    /// Floats a V-cycle's tail from level `first` down needs in one GPU
    /// workgroup (glsl/wind/mg_tail.glsl): every tail level's pressure,
    /// right-hand side and face conductances, and one residual the size
    /// of level `first`.
    pub fn tail_footprint(&self, first: usize) -> usize {
        let tail = &self.levels[first..];
        let cells: usize = tail.iter().map(Level::cell_count).sum();
        let faces: usize = tail.iter().flat_map(|l| &l.conductance).map(Vec::len).sum();
        2 * cells + self.levels[first].cell_count() + faces
    }

    /// The finest level whose tail fits `capacity` floats: the GPU runs
    /// the V-cycle from there down and back up in one workgroup, and each
    /// finer level kernel by kernel. The coarsest level always fits (at
    /// most `MAX_COARSEST_CELLS` cells); None if not even it does.
    pub fn tail_level(&self, capacity: usize) -> Option<usize> {
        (0..self.levels.len()).find(|&l| self.tail_footprint(l) <= capacity)
    }
}

/// Which axes to halve: those with two cells or more whose spacing is
/// within 1.5x of the finest such spacing. Flat cells (the paper's grid has
/// 0.55 x 0.15 x 0.55 m) couple far more strongly along their short side,
/// which a point smoother cannot balance; halving only that side first
/// (semi-coarsening) makes the cells about cubic before halving all three.
fn coarsening(cells: UVec3, spacing: Vec3) -> UVec3 {
    let finest = (0..3)
        .filter(|&a| cells[a] >= 2)
        .map(|a| spacing[a])
        .fold(f32::INFINITY, f32::min);
    UVec3::from_array(std::array::from_fn(|a| {
        if cells[a] >= 2 && spacing[a] <= 1.5 * finest {
            2
        } else {
            1
        }
    }))
}

/// Level `fine` halved along the axes its `ratio` says.
fn coarsen(fine: &Level) -> Level {
    let r = fine.ratio;
    let cells = (fine.cells + r - 1) / r;
    let mut coarse = Level {
        cells,
        ratio: UVec3::ONE,
        conductance: [Vec::new(), Vec::new(), Vec::new()],
    };
    for axis in 0..3 {
        let d = coarse.face_dims(axis);
        let mut k = Vec::with_capacity((d.x * d.y * d.z) as usize);
        for z in 0..d.z {
            for y in 0..d.y {
                for x in 0..d.x {
                    k.push(coarse_conductance(fine, axis, UVec3::new(x, y, z)));
                }
            }
        }
        coarse.conductance[axis] = k;
    }
    coarse
}

/// Conductance of coarse face `f` along `axis`: the fine faces it covers,
/// summed, over the growth of the distance between pressure samples.
fn coarse_conductance(fine: &Level, axis: usize, f: UVec3) -> f32 {
    let r = fine.ratio;
    let mut first = f * r;
    let mut last = (first + r).min(fine.cells);
    // On the face's own axis the coarse face lies on one fine face plane
    // (the last plane where an odd count left a thin coarse cell).
    first[axis] = (f[axis] * r[axis]).min(fine.cells[axis]);
    last[axis] = first[axis] + 1;
    let mut sum = 0.0;
    for z in first.z..last.z {
        for y in first.y..last.y {
            for x in first.x..last.x {
                sum += fine.conductance[axis][fine.face_index(axis, UVec3::new(x, y, z))];
            }
        }
    }
    // The distance between the two pressure samples the face joins, in
    // fine cells: half of each side's width (beyond the grid, the outside
    // sample mirrors the inside cell).
    let n = fine.cells[axis];
    let coarse_count = n.div_ceil(r[axis]);
    let width = |c: u32| coarse_span(c, r[axis], n).1;
    let low = f[axis].checked_sub(1).map(width);
    let high = (f[axis] < coarse_count).then(|| width(f[axis]));
    let distance = match (low, high) {
        (Some(a), Some(b)) => (a + b) / 2.0,
        (Some(a), None) | (None, Some(a)) => a,
        (None, None) => 1.0,
    };
    sum / distance
}

/// Where coarse cell `c` lies along one axis, in fine cells: its centre
/// and its width (`ratio` fine cells, or fewer where an odd count left the
/// last coarse cell thin).
fn coarse_span(c: u32, ratio: u32, fine_count: u32) -> (f32, f32) {
    let start = c * ratio;
    let end = (start + ratio).min(fine_count);
    ((start + end) as f32 / 2.0, (end - start) as f32)
}

/// The weight of coarse cell `coarse` in the interpolated correction of
/// fine cell `fine`, along one axis: linear interpolation between the
/// centres of the fine cell's parent and the parent's neighbour on the fine
/// cell's side (3/4 and 1/4 on a regular halving). Beyond the grid, an
/// open side's outside pressure is zero at one parent width from the
/// parent's centre, and a closed side mirrors the parent (it takes all).
pub fn axis_weight(fine: u32, coarse: u32, ratio: u32, fine_count: u32, open: bool) -> f32 {
    let parent = fine / ratio;
    let x = fine as f32 + 0.5;
    let (centre, width) = coarse_span(parent, ratio, fine_count);
    let coarse_count = fine_count.div_ceil(ratio);
    let neighbour = if x < centre {
        parent.checked_sub(1)
    } else if x > centre {
        Some(parent + 1).filter(|&n| n < coarse_count)
    } else {
        return if coarse == parent { 1.0 } else { 0.0 };
    };
    match neighbour {
        Some(n) => {
            let (other, _) = coarse_span(n, ratio, fine_count);
            let t = (x - centre) / (other - centre);
            if coarse == parent {
                1.0 - t
            } else if coarse == n {
                t
            } else {
                0.0
            }
        }
        None if coarse == parent => {
            if open {
                1.0 - (x - centre).abs() / width
            } else {
                1.0
            }
        }
        None => 0.0,
    }
}

/// The coarse levels' pressure and right-hand side, one vector each.
#[derive(Clone, Debug, Default)]
pub struct Work {
    pressure: Vec<Vec<f32>>,
    rhs: Vec<Vec<f32>>,
}

impl Work {
    fn ensure(&mut self, mg: &Multigrid) {
        if self.pressure.len() + 1 != mg.levels.len() {
            self.pressure = mg.levels[1..]
                .iter()
                .map(|l| vec![0.0; l.cell_count()])
                .collect();
            self.rhs = self.pressure.clone();
        }
    }

    /// Level `l`'s pressure and right-hand side (level 0 is the caller's).
    fn level<'a>(
        &'a mut self,
        l: usize,
        p: &'a mut [f32],
        b: &'a [f32],
    ) -> (&'a mut [f32], &'a [f32]) {
        if l == 0 {
            (p, b)
        } else {
            (&mut self.pressure[l - 1], &self.rhs[l - 1])
        }
    }

    /// Levels `l` and `l + 1` at once: fine p, coarse p, fine b, coarse b.
    fn pair<'a>(
        &'a mut self,
        l: usize,
        p: &'a mut [f32],
        b: &'a [f32],
    ) -> (&'a mut [f32], &'a mut [f32], &'a [f32], &'a mut [f32]) {
        if l == 0 {
            (p, &mut self.pressure[0], b, &mut self.rhs[0])
        } else {
            let (fine_p, coarse_p) = self.pressure.split_at_mut(l);
            let (fine_b, coarse_b) = self.rhs.split_at_mut(l);
            (
                &mut fine_p[l - 1],
                &mut coarse_p[0],
                &fine_b[l - 1],
                &mut coarse_b[0],
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The V-cycle by the operators' lists gives the same bits as by the
    /// definitions, on a grid with odd counts (thin last coarse cells),
    /// flat cells (semi-coarsening), open and closed sides and walls
    /// inside.
    #[test]
    fn the_lists_give_the_v_cycle_of_the_definitions_bit_for_bit() {
        let cells = UVec3::new(13, 6, 9);
        let h = Vec3::new(0.5, 0.2, 0.5);
        // A face is closed where a small hash says so (one in five), and
        // every face of the -z side.
        let free: [Vec<bool>; 3] = std::array::from_fn(|axis| {
            let mut d = cells;
            d[axis] += 1;
            (0..d.x * d.y * d.z)
                .map(|i| {
                    let z = i / (d.x * d.y);
                    let hash = (i.wrapping_mul(2_654_435_761) ^ axis as u32).rotate_left(7);
                    hash % 5 != 0 && !(axis == 2 && z == 0)
                })
                .collect()
        });
        let mg = Multigrid::new(cells, h, &free);
        assert!(mg.levels.len() >= 3, "{} levels", mg.levels.len());
        let n = mg.levels[0].cell_count();
        let b: Vec<f32> = (0..n)
            .map(|i| ((i * 37 % 101) as f32 - 50.0) * 1e-3)
            .collect();
        let (mut fast, mut slow) = (vec![0.0f32; n], vec![0.0f32; n]);
        let (mut work_fast, mut work_slow) = (Work::default(), Work::default());
        for _ in 0..3 {
            mg.v_cycle(&mut fast, &b, &mut work_fast);
            mg.v_cycle_by_definition(&mut slow, &b, &mut work_slow);
        }
        assert!(fast.iter().any(|&v| v != 0.0));
        let differ = fast
            .iter()
            .zip(&slow)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(differ, 0, "{differ} of {n} cells differ");
    }
}
