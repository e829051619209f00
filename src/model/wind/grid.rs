//! The wind grid: its cells, its staggered faces and how both are numbered.

use glam::{UVec3, Vec3};

use crate::error::{Error, Result};

/// The grid: `cells` = (nx, ny, nz), x and z horizontal, y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WindGrid {
    pub cells: UVec3,
    /// World position of the grid's minimum corner.
    pub origin: Vec3,
    /// Size of one cell along x, y, z (metres).
    pub cell: Vec3,
}

/// The most cells one grid may have (the paper's is 72,000).
pub const MAX_CELLS: u64 = 64 * 1024 * 1024;

impl WindGrid {
    pub fn new(cells: UVec3, origin: Vec3, size: Vec3) -> Result<Self> {
        let n = cells.as_u64vec3();
        if cells.min_element() == 0 || n.x * n.y * n.z > MAX_CELLS {
            return Err(Error::InvalidInput(format!(
                "wind grid {}x{}x{} is not allowed, use at least 1 cell per axis and at most {MAX_CELLS} cells",
                cells.x, cells.y, cells.z
            )));
        }
        if !(size.is_finite() && size.min_element() > 0.0 && origin.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "wind domain size {size} at {origin} is not allowed, use finite positive sizes"
            )));
        }
        Ok(Self {
            cells,
            origin,
            cell: size / cells.as_vec3(),
        })
    }

    /// The divergence f32 arithmetic leaves in any field whose faces reach
    /// `max_speed` (m/s) on this grid: each face value rounded by up to
    /// half an ulp of the fastest, six of them over the smallest cell side,
    /// with a factor for the solve's own rounding. Below it a projection
    /// has nothing left to remove (1/s).
    pub fn divergence_floor(&self, max_speed: f32) -> f32 {
        4.0 * f32::EPSILON * max_speed.abs() / self.cell.min_element()
    }

    pub fn cell_count(&self) -> usize {
        (self.cells.x * self.cells.y * self.cells.z) as usize
    }

    /// Faces of all three velocity components: one velocity copy's length.
    pub fn face_count(&self) -> u64 {
        (0..3)
            .map(|a| self.face_dims(a).as_u64vec3().element_product())
            .sum()
    }

    /// Number of samples of velocity component `axis` (one more along its own axis).
    #[inline]
    pub fn face_dims(&self, axis: usize) -> UVec3 {
        let mut d = self.cells;
        d[axis] += 1;
        d
    }

    #[inline]
    pub fn cell_index(&self, i: u32, j: u32, k: u32) -> usize {
        (i + self.cells.x * (j + self.cells.y * k)) as usize
    }

    #[inline]
    pub fn face_index(&self, axis: usize, i: u32, j: u32, k: u32) -> usize {
        let d = self.face_dims(axis);
        (i + d.x * (j + d.y * k)) as usize
    }

    /// World position of face sample (i, j, k) of component `axis`.
    pub fn face_position(&self, axis: usize, i: u32, j: u32, k: u32) -> Vec3 {
        let mut offset = Vec3::splat(0.5);
        offset[axis] = 0.0;
        self.origin + (UVec3::new(i, j, k).as_vec3() + offset) * self.cell
    }

    pub fn cell_center(&self, i: u32, j: u32, k: u32) -> Vec3 {
        self.origin + (UVec3::new(i, j, k).as_vec3() + 0.5) * self.cell
    }

    pub fn size(&self) -> Vec3 {
        self.cell * self.cells.as_vec3()
    }

    /// Every sample of velocity component `axis` in storage order:
    /// (index, [i, j, k]).
    pub fn each_face(self, axis: usize) -> impl Iterator<Item = (usize, [u32; 3])> {
        lattice(self.face_dims(axis))
    }

    /// Every cell in storage order: (index, [i, j, k]).
    pub fn each_cell(self) -> impl Iterator<Item = (usize, [u32; 3])> {
        lattice(self.cells)
    }
}

/// The points of a `d.x` x `d.y` x `d.z` lattice, x fastest, numbered in that order.
fn lattice(d: UVec3) -> impl Iterator<Item = (usize, [u32; 3])> {
    (0..d.z)
        .flat_map(move |k| (0..d.y).flat_map(move |j| (0..d.x).map(move |i| [i, j, k])))
        .enumerate()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_iterators_number_samples_as_storage_does() {
        let grid = WindGrid::new(UVec3::new(3, 2, 4), Vec3::ZERO, Vec3::ONE).unwrap();
        for axis in 0..3 {
            let d = grid.face_dims(axis);
            let all: Vec<_> = grid.each_face(axis).collect();
            assert_eq!(all.len(), (d.x * d.y * d.z) as usize);
            for (idx, [i, j, k]) in all {
                assert_eq!(idx, grid.face_index(axis, i, j, k));
            }
        }
        for (c, [i, j, k]) in grid.each_cell() {
            assert_eq!(c, grid.cell_index(i, j, k));
        }
    }
}
