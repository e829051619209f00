//! What the wind grid's cells and faces are (docs/method.md): a cell is
//! solid where its centre lies under the ground or inside an obstacle, and
//! each face is free, a wall, an inflow or buried by the cells beside it
//! and the grid's sides. `WindField` classifies once, and again when its
//! inflow turns or its window moves over terrain; `Classification` is the
//! same for a grid alone (the GPU's window, uploaded after a move). Uses
//! the grid, its settings and the multigrid.

use super::{Inflow, Side, WindGrid, WindSettings};
use crate::model::multigrid::{Level, Multigrid};

/// How a velocity sample behaves at a boundary.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceKind {
    Free,
    Wall,
    Inflow,
    /// A horizontal component between two cells under the ground: fixed
    /// for the solver, holding the free-slip ghost value of the air above
    /// for the samplers (`WindField::free_slip_under_ground`).
    Buried,
}

/// Which cells lie under the ground, and which are solid (under it or
/// inside an obstacle): a cell's centre decides, so that the ground is a
/// staircase whose treads lie at its height rounded to the nearest face.
pub fn voxelised(grid: &WindGrid, settings: &WindSettings) -> (Vec<bool>, Vec<bool>) {
    let terrain = &settings.terrain;
    let ground: Vec<bool> = grid
        .each_cell()
        .map(|(_, [i, j, k])| {
            let c = grid.cell_center(i, j, k);
            !terrain.is_flat() && c.y < terrain.height(c.x, c.z)
        })
        .collect();
    let solid = grid
        .each_cell()
        .map(|(c, [i, j, k])| {
            ground[c] || {
                let c = grid.cell_center(i, j, k);
                settings.obstacles.iter().any(|o| o.contains(c))
            }
        })
        .collect();
    (ground, solid)
}

/// A grid's solid and ground cells, which the faces' kinds follow from.
pub struct Cells<'a> {
    pub grid: &'a WindGrid,
    pub solid: &'a [bool],
    pub ground: &'a [bool],
}

impl Cells<'_> {
    /// Every face's kind for `inflow` (its entry, exit and along sides).
    pub fn face_kinds(&self, inflow: Option<&Inflow>) -> [Vec<FaceKind>; 3] {
        [0, 1, 2].map(|axis| {
            self.grid
                .each_face(axis)
                .map(|(_, f)| self.classify(axis, f, inflow))
                .collect()
        })
    }

    fn is_solid(&self, c: [i64; 3]) -> bool {
        let n = self.grid.cells;
        if c[0] < 0
            || c[1] < 0
            || c[2] < 0
            || c[0] >= n.x as i64
            || c[1] >= n.y as i64
            || c[2] >= n.z as i64
        {
            return false;
        }
        self.solid[self.grid.cell_index(c[0] as u32, c[1] as u32, c[2] as u32)]
    }

    /// Whether cell `c` lies under the ground; a cell beyond the grid's
    /// side across `axis` counts as the one inside.
    fn is_ground(&self, mut c: [i64; 3], axis: usize) -> bool {
        let n = self.grid.cells[axis] as i64;
        c[axis] = c[axis].clamp(0, n - 1);
        self.ground[self.grid.cell_index(c[0] as u32, c[1] as u32, c[2] as u32)]
    }

    /// How a face behaves: its value is fixed (no-through walls, solids,
    /// inflow) or free (moved by advection, forces and projection).
    fn classify(&self, axis: usize, f: [u32; 3], inflow: Option<&Inflow>) -> FaceKind {
        let n = self.grid.cells;
        let lo = [f[0] as i64, f[1] as i64, f[2] as i64];
        let mut left = lo;
        left[axis] -= 1;
        if self.is_ground(lo, axis) && self.is_ground(left, axis) && axis != 1 {
            return FaceKind::Buried;
        }
        if self.is_solid(lo) || self.is_solid(left) {
            return FaceKind::Wall;
        }
        if axis == 1 && (f[1] == 0 || f[1] == n.y) {
            return FaceKind::Wall; // ground and top: nothing passes through
        }
        if let Some(inflow) = inflow {
            if axis != 1 && (f[axis] == 0 || f[axis] == n[axis]) {
                // The sides along the inflow are free-slip, as a wind
                // tunnel's: open, they let the incoming air leave sideways
                // before it crosses the field (on a 7 m wide strip it died
                // out within 20 m), where in a wide field it would go on.
                return match inflow.side(axis, (f[axis] > 0) as u32) {
                    Side::Entry => FaceKind::Inflow,
                    Side::Along => FaceKind::Wall,
                    Side::Exit => FaceKind::Free,
                };
            }
        }
        FaceKind::Free
    }
}

/// Which faces are free, per axis: what the multigrid's conductances
/// follow.
fn free_faces(faces: &[Vec<FaceKind>; 3]) -> [Vec<bool>; 3] {
    faces
        .each_ref()
        .map(|kinds| kinds.iter().map(|&k| k == FaceKind::Free).collect())
}

/// The multigrid hierarchy of a grid's free faces.
pub fn multigrid_of(grid: &WindGrid, faces: &[Vec<FaceKind>; 3]) -> Multigrid {
    Multigrid::new(grid.cells, grid.cell, &free_faces(faces))
}

/// A grid's cells and faces over the scene's ground and obstacles for its
/// inflow, as `WindField::new` classifies them, with the multigrid's
/// levels over them (not the CPU's operators: what the GPU reads).
pub struct Classification {
    pub solid: Vec<bool>,
    pub faces: [Vec<FaceKind>; 3],
    pub levels: Vec<Level>,
}

impl Classification {
    pub fn of(grid: &WindGrid, settings: &WindSettings) -> Self {
        let (ground, solid) = voxelised(grid, settings);
        let cells = Cells {
            grid,
            solid: &solid,
            ground: &ground,
        };
        let faces = cells.face_kinds(settings.inflow.as_ref());
        let levels = Multigrid::levels_of(grid.cells, grid.cell, &free_faces(&faces));
        Self {
            solid,
            faces,
            levels,
        }
    }
}
