//! The ground's height field drawn (src/model/terrain.rs): an indexed
//! grid of triangles made once on the CPU, drawn in the colour pass
//! (glsl/terrain/: soil-textured, lit, shadowed by the grass and the
//! hills) and into the shadow map (a hill shades the grass behind
//! it at a low sun). It covers the square where the ground is clear and
//! its haze thickens to the horizon's colour; beyond, the flat ground the
//! backdrop draws reaches the horizon, hidden by that haze. Flat ground
//! has no mesh: the backdrop alone draws it, as before.
//!
//! The grid is graded: under the grass its spacing keeps the drawn
//! surface within `SAG_M` of the true one (where the blades are rooted),
//! and outside it each row of quads is `GROWTH` times wider than the one
//! before, out to the haze. Its outermost ring lies at y = 0, where the
//! backdrop's plane takes over, so the two meet without a step whatever
//! the terrain's height there.
//!
//! Into the shadow map go only the triangles facing away from the sun
//! (the terrain shadow pipeline culls the others): a ray from a receiver
//! in a hill's shadow leaves the air through such a face, so they hold
//! every shadow the terrain casts, and the sunlit slopes, most of the
//! map, are not drawn twice.

use ash::vk;
use glam::Vec3;

use crate::error::Result;
use crate::gpu::{Access, Buffer, CommandPool, Gpu, Pipeline, Recording};
use crate::model::terrain::Terrain;
use crate::scene::Scene;

/// One corner of the terrain's grid (`terrain.vert`'s inputs).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct TerrainVertex {
    pub position: [f32; 3],
    /// The ground's upward unit normal.
    pub normal: [f32; 3],
}

/// How far the drawn ground may lie from the true one under the grass
/// (m): the blades stand on the true surface.
pub const SAG_M: f32 = 0.01;

/// Each row of quads beyond the grass this much wider than the last.
const GROWTH: f32 = 1.15;

/// Bounds on the spacing under the grass (m), and on its rows along a side.
const FINEST_M: f32 = 0.05;
const COARSEST_M: f32 = 1.0;
const MAX_FINE_ROWS: f32 = 512.0;

/// Half the side of the square the mesh covers, about the grass's centre:
/// the clear radius and three haze lengths beyond it (glsl/common/soil.glsl's
/// haze is 95% of the horizon there).
pub fn half_side(clear: f32) -> f32 {
    clear + 3.0 * (0.25 * clear + 10.0)
}

/// The terrain's triangles, indexed.
#[derive(Clone, Debug, Default)]
pub struct Grid {
    pub vertices: Vec<TerrainVertex>,
    /// Three per triangle, counter-clockwise seen from above.
    pub indices: Vec<u32>,
}

/// A cover's terrain mesh is made around the camera's position rounded
/// to a lattice of this spacing (m): remade each time the camera crosses
/// into another square of it, and the same wherever in the square the
/// camera is.
pub const COVER_MESH_STEP_M: f32 = 8.0;

/// The centre (x, z) of the scene's terrain mesh with the camera at `eye`:
/// the grass's centre, or a cover's, `eye` rounded to
/// `COVER_MESH_STEP_M` (the cover grows around the camera).
pub fn mesh_centre(scene: &Scene, eye: Vec3) -> [f32; 2] {
    match scene.grass.cover {
        Some(_) => {
            let snap = |v: f32| (v / COVER_MESH_STEP_M).round() * COVER_MESH_STEP_M;
            [snap(eye.x), snap(eye.z)]
        }
        None => {
            let c = scene.grass_center();
            [c.x, c.z]
        }
    }
}

/// The scene's terrain mesh with the camera at `eye`, about `mesh_centre`;
/// None for flat ground.
pub fn mesh(scene: &Scene, eye: Vec3) -> Option<Grid> {
    let terrain = scene.ground.terrain();
    if terrain.is_flat() {
        return None;
    }
    let centre = mesh_centre(scene, eye);
    let half = half_side(scene.ground.half_extent);
    let edge = (
        [centre[0] - half, centre[1] - half],
        [centre[0] + half, centre[1] + half],
    );
    // The fine part: the grass's footprint and the reach of its tallest
    // blade (a point just beside it when there is none); a cover's, its
    // view distance around the camera wherever in the centre's square it
    // is.
    let (mut lo, mut hi) = match &scene.grass.cover {
        Some(c) => {
            let reach = c.view_distance + COVER_MESH_STEP_M + scene.grass.shape.height[1];
            (
                [centre[0] - reach, centre[1] - reach],
                [centre[0] + reach, centre[1] + reach],
            )
        }
        None => scene.grass_reach_bounds(),
    };
    for a in 0..2 {
        if lo[a] > hi[a] {
            (lo[a], hi[a]) = (edge.0[a] + half, edge.0[a] + half);
        }
        lo[a] = lo[a].max(edge.0[a]);
        hi[a] = hi[a].min(edge.1[a]);
    }
    Some(grid(&terrain, edge, (lo, hi)))
}

/// The graded grid over the square `edge` (lowest and highest x, z), fine
/// over `fine`.
fn grid(terrain: &Terrain, edge: ([f32; 2], [f32; 2]), fine: ([f32; 2], [f32; 2])) -> Grid {
    let step = fine_step(terrain, fine);
    let xs = axis((edge.0[0], edge.1[0]), (fine.0[0], fine.1[0]), step);
    let zs = axis((edge.0[1], edge.1[1]), (fine.0[1], fine.1[1]), step);
    let spacing = |v: &[f32], i: usize| {
        let (a, b) = (v[i.saturating_sub(1)], v[(i + 1).min(v.len() - 1)]);
        (b - a) / (if i == 0 || i == v.len() - 1 { 1.0 } else { 2.0 })
    };
    let (nx, nz) = (xs.len(), zs.len());
    let mut vertices = Vec::with_capacity(nx * nz);
    for (k, &z) in zs.iter().enumerate() {
        for (i, &x) in xs.iter().enumerate() {
            let outermost = i == 0 || k == 0 || i == nx - 1 || k == nz - 1;
            let smoothing = 0.5 * spacing(&xs, i).min(spacing(&zs, k));
            vertices.push(TerrainVertex {
                position: [x, if outermost { 0.0 } else { terrain.height(x, z) }, z],
                normal: terrain.normal(x, z, smoothing).to_array(),
            });
        }
    }
    let mut indices = Vec::with_capacity(6 * (nx - 1) * (nz - 1));
    for k in 0..nz - 1 {
        for i in 0..nx - 1 {
            let at = |i: usize, k: usize| (k * nx + i) as u32;
            let (a, b, c, d) = (at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1));
            // Counter-clockwise seen from above (+y): a, d, c and a, c, b.
            indices.extend([a, d, c, a, c, b]);
        }
    }
    Grid { vertices, indices }
}

/// The spacing under the grass that keeps the drawn surface within
/// `SAG_M` of the true one: a linear triangle's error is at most a
/// quarter of the curvature times its side squared.
fn fine_step(terrain: &Terrain, (lo, hi): ([f32; 2], [f32; 2])) -> f32 {
    let e = 0.1;
    let n = 64;
    let mut curvature = 1e-6f32;
    for j in 0..=n {
        for i in 0..=n {
            let x = lo[0] + (hi[0] - lo[0]) * i as f32 / n as f32;
            let z = lo[1] + (hi[1] - lo[1]) * j as f32 / n as f32;
            let h = |dx: f32, dz: f32| terrain.height(x + dx, z + dz);
            let c = h(0.0, 0.0);
            let along = |u: f32, v: f32| (h(u, v) - 2.0 * c + h(-u, -v)).abs() / (u * u + v * v);
            curvature = curvature
                .max(along(e, 0.0))
                .max(along(0.0, e))
                .max(along(e, e))
                .max(along(e, -e));
        }
    }
    let longest = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    (4.0 * SAG_M / curvature)
        .sqrt()
        .clamp(FINEST_M, COARSEST_M)
        .max(longest / MAX_FINE_ROWS)
}

/// The grid lines along one axis: evenly `step` apart (or a little less)
/// over `fine`, then each gap `GROWTH` times the last out to `edge`.
fn axis(edge: (f32, f32), fine: (f32, f32), step: f32) -> Vec<f32> {
    let f0 = fine.0.max(edge.0);
    let f1 = fine.1.min(edge.1).max(f0);
    let cells = ((f1 - f0) / step).ceil().max(1.0) as usize;
    let mut lines: Vec<f32> = (0..=cells)
        .map(|i| f0 + (f1 - f0) * i as f32 / cells as f32)
        .collect();
    let outward = |from: f32, to: f32| {
        let sign = (to - from).signum();
        let mut out = Vec::new();
        let (mut at, mut gap) = (from, step);
        while (to - at) * sign > 1e-4 {
            gap *= GROWTH;
            // The last gap takes the rest rather than leave a sliver.
            at = if (to - at) * sign < 1.5 * gap {
                to
            } else {
                at + sign * gap
            };
            out.push(at);
        }
        out
    };
    let below = outward(f0, edge.0);
    let above = outward(f1, edge.1);
    lines.splice(0..0, below.into_iter().rev());
    lines.extend(above);
    lines
}

/// The terrain's mesh on the GPU.
pub struct TerrainMesh {
    vertices: Buffer,
    indices: Buffer,
    count: u32,
}

impl TerrainMesh {
    pub fn new(gpu: &Gpu, commands: &CommandPool, grid: &Grid) -> Result<Self> {
        Ok(Self {
            vertices: Buffer::with_data(
                gpu,
                commands,
                "terrain mesh vertices (vertex buffer)",
                bytemuck::cast_slice(&grid.vertices),
                vk::BufferUsageFlags::VERTEX_BUFFER,
                Access::VERTEX_INPUT,
            )?,
            indices: Buffer::with_data(
                gpu,
                commands,
                "terrain mesh triangles (index buffer)",
                bytemuck::cast_slice(&grid.indices),
                vk::BufferUsageFlags::INDEX_BUFFER,
                Access::INDEX_INPUT,
            )?,
            count: grid.indices.len() as u32,
        })
    }

    /// Draws the terrain with `pipeline` (the terrain pipeline, or the
    /// terrain shadow pipeline), its set already bound.
    pub fn draw(&self, rec: &Recording, pipeline: &Pipeline) {
        rec.bind_pipeline(pipeline);
        rec.bind_vertex_buffer(&self.vertices);
        rec.bind_index_buffer(&self.indices);
        rec.draw_indexed(self.count);
    }
}

/// The lowest ground under the terrain mesh's square with the camera at
/// `eye` (the shadows the cull pass follows down to it; 0 on flat ground).
pub fn lowest(scene: &Scene, eye: Vec3) -> f32 {
    let terrain = scene.ground.terrain();
    if terrain.is_flat() {
        return 0.0;
    }
    let c = mesh_centre(scene, eye);
    let half = half_side(scene.ground.half_extent);
    terrain
        .range_over(
            [c[0] - half, c[1] - half],
            [c[0] + half, c[1] + half],
            half / 64.0,
        )
        .0
        .min(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::terrain::{Hill, Ridge};

    fn hills() -> Terrain {
        Terrain {
            hills: vec![Hill {
                center: [1.0, 2.0],
                height: 3.0,
                half_width: 4.0,
            }],
            ridges: vec![Ridge {
                center: [0.0, 0.0],
                height: 1.6,
                half_width: 3.0,
                heading: 100.0,
            }],
            ..Terrain::default()
        }
    }

    /// The grid lines of `grid` along x and along z.
    fn lines(grid: &Grid) -> (Vec<f32>, Vec<f32>) {
        let first_z = grid.vertices[0].position[2];
        let xs: Vec<f32> = grid
            .vertices
            .iter()
            .take_while(|v| v.position[2] == first_z)
            .map(|v| v.position[0])
            .collect();
        let zs = grid
            .vertices
            .iter()
            .step_by(xs.len())
            .map(|v| v.position[2])
            .collect();
        (xs, zs)
    }

    #[test]
    fn the_mesh_lies_on_the_ground_faces_up_and_meets_the_plane_at_its_edge() {
        let terrain = hills();
        let grid = grid(
            &terrain,
            ([-40.0, -40.0], [40.0, 40.0]),
            ([-8.0, -5.0], [8.0, 5.0]),
        );
        let (xs, zs) = lines(&grid);
        assert_eq!(grid.vertices.len(), xs.len() * zs.len());
        assert_eq!(grid.indices.len(), 6 * (xs.len() - 1) * (zs.len() - 1));
        assert_eq!((xs[0], *xs.last().unwrap()), (-40.0, 40.0));
        assert_eq!((zs[0], *zs.last().unwrap()), (-40.0, 40.0));
        for t in grid.indices.chunks(3) {
            let p: Vec<Vec3> = t
                .iter()
                .map(|&i| Vec3::from(grid.vertices[i as usize].position))
                .collect();
            let up = (p[1] - p[0]).cross(p[2] - p[0]);
            assert!(up.y > 0.0, "{p:?}");
        }
        for v in &grid.vertices {
            let [x, y, z] = v.position;
            let edge = x.abs() == 40.0 || z.abs() == 40.0;
            assert_eq!(y, if edge { 0.0 } else { terrain.height(x, z) });
            assert!(Vec3::from(v.normal).y > 0.0);
        }
    }

    /// Under the grass the drawn ground is within `SAG_M` of the true one
    /// (measured between the lines, where a flat triangle strays most);
    /// beyond it the rows widen, so the mesh is a fraction of a uniform
    /// one as fine.
    #[test]
    fn under_the_grass_the_mesh_keeps_to_the_ground_and_beyond_it_coarsens() {
        let terrain = hills();
        let fine = ([-8.0, -5.0], [8.0, 5.0]);
        let grid = grid(&terrain, ([-40.0, -40.0], [40.0, 40.0]), fine);
        let (xs, zs) = lines(&grid);
        let y = |i: usize, k: usize| grid.vertices[k * xs.len() + i].position[1];
        let mut worst = 0f32;
        for k in 0..zs.len() - 1 {
            for i in 0..xs.len() - 1 {
                if xs[i] < fine.0[0]
                    || xs[i + 1] > fine.1[0]
                    || zs[k] < fine.0[1]
                    || zs[k + 1] > fine.1[1]
                {
                    continue;
                }
                for (u, v) in [
                    (0.5, 0.5),
                    (0.25, 0.75),
                    (0.75, 0.25),
                    (0.5, 0.1),
                    (0.1, 0.5),
                ] {
                    let x = xs[i] + u * (xs[i + 1] - xs[i]);
                    let z = zs[k] + v * (zs[k + 1] - zs[k]);
                    // The quad's two triangles share the diagonal a-c.
                    let drawn = if v > u {
                        y(i, k) + u * (y(i + 1, k + 1) - y(i, k + 1)) + v * (y(i, k + 1) - y(i, k))
                    } else {
                        y(i, k) + u * (y(i + 1, k) - y(i, k)) + v * (y(i + 1, k + 1) - y(i + 1, k))
                    };
                    worst = worst.max((drawn - terrain.height(x, z)).abs());
                }
            }
        }
        eprintln!("deepest sag under the grass: {:.2} mm", worst * 1e3);
        assert!(worst <= SAG_M, "the mesh strays {worst} m from the ground");
        assert!(worst > 0.1 * SAG_M, "finer than it need be: {worst} m");
        let gaps: Vec<f32> = xs.windows(2).map(|w| w[1] - w[0]).collect();
        let outer: Vec<&f32> = gaps
            .iter()
            .filter(|&&g| g > 1.01 * gaps[gaps.len() / 2])
            .collect();
        assert!(!outer.is_empty());
        assert!(
            grid.vertices.len() < 161 * 161 / 2,
            "{} vertices",
            grid.vertices.len()
        );
    }
}
