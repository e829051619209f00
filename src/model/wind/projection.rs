//! Kernels 3-5: the divergence, the pressure (Jacobi or multigrid V-cycles)
//! and the gradient subtracted, which leave the wind divergence-free.

use super::{FaceKind, WindField};
use crate::model::multigrid::{Multigrid, Solve};

impl WindField {
    /// Kernel 3: divergence of each fluid cell, sum over axes of (out - in) / h.
    pub fn compute_divergence(&mut self) {
        for (c, [i, j, k]) in self.grid.each_cell() {
            self.divergence[c] = if self.solid[c] {
                0.0
            } else {
                self.cell_divergence(i, j, k)
            };
        }
    }

    pub fn cell_divergence(&self, i: u32, j: u32, k: u32) -> f32 {
        let mut div = 0.0;
        for axis in 0..3 {
            let mut hi = [i, j, k];
            hi[axis] += 1;
            let a = self.vel[axis][self.grid.face_index(axis, i, j, k)];
            let b = self.vel[axis][self.grid.face_index(axis, hi[0], hi[1], hi[2])];
            div += (b - a) / self.grid.cell[axis];
        }
        div
    }

    /// Largest |divergence| over the fluid cells.
    pub fn max_divergence(&self) -> f32 {
        self.grid
            .each_cell()
            .filter(|&(c, _)| !self.solid[c])
            .map(|(_, [i, j, k])| self.cell_divergence(i, j, k).abs())
            .fold(0.0, f32::max)
    }

    /// Root mean square divergence over the fluid cells: the max norm
    /// follows the slowest Jacobi modes, this the field as a whole.
    pub fn rms_divergence(&self) -> f32 {
        let (sum, n) = self
            .grid
            .each_cell()
            .filter(|&(c, _)| !self.solid[c])
            .map(|(_, [i, j, k])| (self.cell_divergence(i, j, k) as f64).powi(2))
            .fold((0.0, 0usize), |(s, n), d| (s + d, n + 1));
        (sum / n.max(1) as f64).sqrt() as f32
    }

    /// Kernel 4: Jacobi iterations for the pressure (with dt/rho folded in):
    /// sum over free faces of (p_nb - p) / h^2 = div. Across a wall face
    /// the term drops (Neumann); outside an open side p = 0 (Dirichlet).
    ///
    /// Warm start (ours): the iterations begin from the previous step's
    /// pressure, so the solve converges across steps and the pressure
    /// reaches across the whole grid although each step runs only a few
    /// dozen iterations.
    pub fn solve_pressure(&mut self, iterations: u32) {
        let mut next = self.pressure.clone();
        for _ in 0..iterations {
            for (c, [i, j, k]) in self.grid.each_cell() {
                next[c] = if self.solid[c] {
                    0.0
                } else {
                    self.jacobi_cell(i, j, k)
                };
            }
            std::mem::swap(&mut self.pressure, &mut next);
        }
    }

    /// Kernel 4 of the multigrid solver: V-cycles on the same equation
    /// from zero, the last step's pressure or the last two carried on,
    /// whichever leaves the least, until
    /// at most `tolerance` of the divergence is left or `max_cycles` ran
    /// (`Multigrid::solve`); kept as `last_solve`.
    pub fn solve_pressure_multigrid(&mut self, max_cycles: u32, tolerance: f32) -> Solve {
        let b = Multigrid::rhs_from_divergence(self.grid.cell, &self.divergence);
        self.last_solve = self.multigrid.solve(
            [&mut self.pressure, &mut self.pressure_before],
            &b,
            &mut self.multigrid_work,
            max_cycles,
            tolerance,
        );
        self.last_solve
    }

    fn jacobi_cell(&self, i: u32, j: u32, k: u32) -> f32 {
        let n = self.grid.cells;
        let mut sum = 0.0;
        let mut weight = 0.0;
        for axis in 0..3 {
            let inv_h2 = 1.0 / (self.grid.cell[axis] * self.grid.cell[axis]);
            for side in [0u32, 1] {
                // The face between this cell and the neighbour on `side`.
                let mut f = [i, j, k];
                f[axis] += side;
                // Fixed faces (walls, inflow): no pressure term (Neumann).
                if self.faces[axis][self.grid.face_index(axis, f[0], f[1], f[2])] != FaceKind::Free
                {
                    continue;
                }
                let mut nb = [i as i64, j as i64, k as i64];
                nb[axis] += if side == 1 { 1 } else { -1 };
                let outside = nb[axis] < 0 || nb[axis] >= n[axis] as i64;
                let p_nb = if outside {
                    0.0
                } else {
                    self.pressure[self
                        .grid
                        .cell_index(nb[0] as u32, nb[1] as u32, nb[2] as u32)]
                };
                sum += p_nb * inv_h2;
                weight += inv_h2;
            }
        }
        if weight == 0.0 {
            return 0.0;
        }
        (sum - self.divergence[self.grid.cell_index(i, j, k)]) / weight
    }

    /// Kernel 5: subtract the pressure gradient from every free face,
    /// (p_right - p_left) / h, with p = 0 outside an open side.
    pub fn subtract_gradient(&mut self) {
        let n = self.grid.cells;
        for axis in 0..3 {
            for (idx, f) in self.grid.each_face(axis) {
                if self.faces[axis][idx] != FaceKind::Free {
                    continue;
                }
                let p_right = if f[axis] < n[axis] {
                    self.pressure[self.grid.cell_index(f[0], f[1], f[2])]
                } else {
                    0.0
                };
                let p_left = if f[axis] > 0 {
                    let mut l = f;
                    l[axis] -= 1;
                    self.pressure[self.grid.cell_index(l[0], l[1], l[2])]
                } else {
                    0.0
                };
                self.vel[axis][idx] -= (p_right - p_left) / self.grid.cell[axis];
            }
        }
    }
}
