//! Reading the wind: trilinear samples of the staggered components, the
//! velocity at a cell and at a point, the wind a blade's tip feels.

use glam::{UVec3, Vec3};

use super::{WindField, RANGE_SNAP};

impl WindField {
    /// Trilinear sample of component `axis` at world position `x`, clamped
    /// to the component's sample lattice.
    pub fn sample_component(&self, vel: &[f32], axis: usize, x: Vec3) -> f32 {
        let d = self.grid.face_dims(axis);
        let g = self.lattice_point(axis, x);
        // g is clamped to at least zero, where truncation is the floor.
        let i0 = g.as_uvec3().min(d - 1);
        let f = g - i0.as_vec3();
        // The step to the next sample along each axis: none at the last.
        let step = |a: usize, stride: u32| {
            if i0[a] + 1 < d[a] {
                stride as usize
            } else {
                0
            }
        };
        let (sx, sy, sz) = (step(0, 1), step(1, d.x), step(2, d.x * d.y));
        let base = (i0.x + d.x * (i0.y + d.y * i0.z)) as usize;
        let row = |o: usize| vel[o] * (1.0 - f.x) + vel[o + sx] * f.x;
        let c00 = row(base);
        let c10 = row(base + sy);
        let c01 = row(base + sz);
        let c11 = row(base + sy + sz);
        let c0 = c00 * (1.0 - f.y) + c10 * f.y;
        let c1 = c01 * (1.0 - f.y) + c11 * f.y;
        c0 * (1.0 - f.z) + c1 * f.z
    }

    /// The least and greatest of the eight samples `sample_component`
    /// interpolates at `x`: the range MacCormack's corrector is clamped to.
    /// Along an axis where the point lies within `RANGE_SNAP` of a
    /// lattice plane, only that plane's samples count: there the
    /// interpolation is continuous but the eight samples are not (a hair
    /// below the plane takes the row beyond it), and a back trace along a
    /// component near zero lands there, where the GPU's rounding and the
    /// CPU's would pick different rows, and a wind turned a quarter
    /// another row than the unturned one.
    pub fn sample_range(&self, vel: &[f32], axis: usize, x: Vec3) -> (f32, f32) {
        let g = self.lattice_point(axis, x);
        let d = self.grid.face_dims(axis);
        let on = (g - g.round()).abs().cmplt(Vec3::splat(RANGE_SNAP));
        let i0 = Vec3::select(on, g.round(), g.floor()).as_uvec3().min(d - 1);
        let i1 = UVec3::select(on, i0, (i0 + 1).min(d - 1));
        self.corners(axis, i0, i1)
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &i| {
                (lo.min(vel[i]), hi.max(vel[i]))
            })
    }

    /// `x` in the sample lattice of component `axis`, clamped to it.
    fn lattice_point(&self, axis: usize, x: Vec3) -> Vec3 {
        let d = self.grid.face_dims(axis);
        let mut offset = Vec3::splat(0.5);
        offset[axis] = 0.0;
        let g = (x - self.grid.origin) / self.grid.cell - offset;
        g.clamp(Vec3::ZERO, (d - 1).as_vec3())
    }

    /// The face indices of component `axis`'s samples at the corners
    /// `i0` and `i1` span (x fastest, then y, then z).
    fn corners(&self, axis: usize, i0: UVec3, i1: UVec3) -> [usize; 8] {
        let d = self.grid.face_dims(axis);
        let at = |i: u32, j: u32, k: u32| (i + d.x * (j + d.y * k)) as usize;
        [
            at(i0.x, i0.y, i0.z),
            at(i1.x, i0.y, i0.z),
            at(i0.x, i1.y, i0.z),
            at(i1.x, i1.y, i0.z),
            at(i0.x, i0.y, i1.z),
            at(i1.x, i0.y, i1.z),
            at(i0.x, i1.y, i1.z),
            at(i1.x, i1.y, i1.z),
        ]
    }

    /// The velocity at the centre of cell (i, j, k): each component the
    /// mean of the cell's two faces across its axis.
    pub fn cell_velocity(&self, i: u32, j: u32, k: u32) -> Vec3 {
        let mean = |axis: usize| {
            let mut hi = [i, j, k];
            hi[axis] += 1;
            let a = self.vel[axis][self.grid.face_index(axis, i, j, k)];
            let b = self.vel[axis][self.grid.face_index(axis, hi[0], hi[1], hi[2])];
            0.5 * (a + b)
        };
        Vec3::new(mean(0), mean(1), mean(2))
    }

    /// The cell holding the world point `x`, or None outside the grid.
    pub fn cell_at(&self, x: Vec3) -> Option<usize> {
        let g = ((x - self.grid.origin) / self.grid.cell).floor();
        let inside = g.cmpge(Vec3::ZERO).all() && g.cmplt(self.grid.cells.as_vec3()).all();
        inside.then(|| {
            let g = g.as_uvec3();
            self.grid.cell_index(g.x, g.y, g.z)
        })
    }

    /// Wind velocity at a world position (what a blade tip samples).
    pub fn sample(&self, x: Vec3) -> Vec3 {
        Vec3::new(
            self.sample_component(&self.vel[0], 0, x),
            self.sample_component(&self.vel[1], 1, x),
            self.sample_component(&self.vel[2], 2, x),
        )
    }

    /// The wind a blade's tip at `x` feels: the grid's (`sample`) and the
    /// turbulence's modes finer than the grid summed there
    /// (glsl/grass/step.glsl the same).
    pub fn felt(&self, x: Vec3) -> Vec3 {
        let wind = self.sample(x);
        if self.subgrid_turbulence.is_empty() {
            return wind;
        }
        let at = x - self.grid.origin;
        wind + crate::model::turbulence::velocity_at(&self.subgrid_turbulence, at)
    }
}
