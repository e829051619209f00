//! Kernel 2: the advection (the paper's semi-Lagrangian step, MacCormack's
//! corrector by default) with the canopy's drag.

use glam::Vec3;

use super::{Advection, FaceKind, Inflow, WindField};

impl WindField {
    /// Kernel 2: advection. Each free face traces back by dt along the
    /// velocity there and takes the value it finds (semi-Lagrangian, the
    /// paper's); MacCormack's corrector (`wind.advection = "maccormack"`,
    /// the default) traces that result forward again, adds half the
    /// difference from the value it started with (the first-order step's
    /// error, so second order), and clamps the sum to the range of the
    /// eight values the back trace interpolated (no new extremes). Then the canopy drag with
    /// coefficient `canopy_drag` (0: none) slows it, implicitly, by the
    /// speed at the face before advection: u' = u / (1 + dt C_d a |u|)
    /// (src/model/canopy.rs).
    ///
    /// Air traced back beyond an inflow's entry side comes from outside:
    /// a horizontal component traced across the other horizontal axis's
    /// entry side takes the inflow's (`Inflow::entering`), uncorrected;
    /// one traced across its own axis's finds the entry faces in its
    /// lattice.
    pub fn advect(
        &mut self,
        dt: f32,
        canopy_drag: f32,
        inflow: Option<&Inflow>,
        scheme: Advection,
    ) {
        let src = self.vel.clone();
        // The semi-Lagrangian step of every free face (the predictor),
        // whether it came from outside, and the velocity it traced with.
        let mut predicted = src.clone();
        let mut traced: [Vec<Option<(Vec3, bool)>>; 3] =
            [0, 1, 2].map(|a| vec![None; src[a].len()]);
        for axis in 0..3 {
            for (idx, [i, j, k]) in self.grid.each_face(axis) {
                if self.faces[axis][idx] != FaceKind::Free {
                    continue;
                }
                let x = self.grid.face_position(axis, i, j, k);
                let v = Vec3::new(
                    self.sample_component(&src[0], 0, x),
                    self.sample_component(&src[1], 1, x),
                    self.sample_component(&src[2], 2, x),
                );
                let back = x - dt * v;
                let entering = inflow.and_then(|i| i.entering(axis, &self.grid, back, self.time));
                predicted[axis][idx] =
                    entering.unwrap_or_else(|| self.sample_component(&src[axis], axis, back));
                traced[axis][idx] = Some((v, entering.is_some()));
            }
        }
        for axis in 0..3 {
            for (idx, [i, j, k]) in self.grid.each_face(axis) {
                let Some((v, entered)) = traced[axis][idx] else {
                    continue;
                };
                let mut u = predicted[axis][idx];
                if scheme == Advection::Maccormack && !entered {
                    let x = self.grid.face_position(axis, i, j, k);
                    let again = self.sample_component(&predicted[axis], axis, x + dt * v);
                    let (lo, hi) = self.sample_range(&src[axis], axis, x - dt * v);
                    // max then min: a NaN stays a NaN rather than a panic.
                    u = (u + 0.5 * (src[axis][idx] - again)).max(lo).min(hi);
                }
                if canopy_drag > 0.0 {
                    let a = self.face_canopy_density(axis, [i, j, k]);
                    u /= 1.0 + dt * canopy_drag * a * v.length();
                }
                self.vel[axis][idx] = u;
            }
        }
    }

    /// The frontal area per unit volume (1/m) at face `f` of component
    /// `axis`: the mean of the two cells it parts (the one inside, at the
    /// grid's sides), from the counts as the GPU reads them:
    /// (c_left + c_right) * (unit / 2 / cell volume).
    pub fn face_canopy_density(&self, axis: usize, f: [u32; 3]) -> f32 {
        let n = self.grid.cells[axis];
        let mut left = f;
        left[axis] = f[axis].max(1) - 1;
        let mut right = f;
        right[axis] = f[axis].min(n - 1);
        let count = |c: [u32; 3]| self.canopy[self.grid.cell_index(c[0], c[1], c[2])] as f32;
        (count(left) + count(right)) * self.canopy_density_per_count()
    }

    /// unit / 2 / cell volume: what one count on each side of a face adds
    /// to the face's frontal area per unit volume (1/m).
    pub fn canopy_density_per_count(&self) -> f32 {
        self.canopy_unit * 0.5 / self.grid.cell.element_product()
    }
}
