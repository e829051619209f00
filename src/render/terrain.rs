//! The ground's height field drawn (src/model/terrain.rs): a grid of
//! triangles made once on the CPU, drawn with the obstacles' pipelines in
//! the colour pass (soil-textured, lit, shadowed by the grass and the
//! hills) and into the shadow map (a hill shades the grass behind it at a
//! low sun). It covers the square where the ground is clear and its haze
//! thickens to the horizon's colour; beyond, the flat ground the
//! backdrop draws reaches the horizon, hidden by that haze. Flat ground
//! has no mesh: the backdrop alone draws it, as before.

use glam::Vec3;

use crate::model::terrain::Terrain;
use crate::render::obstacles::ObstacleVertex;
use crate::scene::Scene;

/// Quads along each side of the mesh.
pub const QUADS: usize = 160;

/// The albedo a soil vertex carries: a red below zero tells
/// glsl/obstacle/obstacle.frag to shade it as the ground (glsl/common/soil.glsl).
pub const SOIL: Vec3 = Vec3::new(-1.0, 0.0, 0.0);

/// Half the side of the square the mesh covers, about the grass's centre:
/// the clear radius and three haze lengths beyond it (glsl/common/soil.glsl's
/// haze is 95% of the horizon there).
pub fn half_side(clear: f32) -> f32 {
    clear + 3.0 * (0.25 * clear + 10.0)
}

/// The scene's terrain mesh: a triangle list, empty for flat ground.
pub fn mesh(scene: &Scene) -> Vec<ObstacleVertex> {
    let terrain = scene.ground.terrain();
    if terrain.is_flat() {
        return Vec::new();
    }
    let centre = scene.grass_center();
    grid(
        &terrain,
        [centre.x, centre.z],
        half_side(scene.ground.half_extent),
    )
}

fn grid(terrain: &Terrain, centre: [f32; 2], half: f32) -> Vec<ObstacleVertex> {
    let step = 2.0 * half / QUADS as f32;
    let corner = |i: usize, k: usize| {
        let (x, z) = (
            centre[0] - half + i as f32 * step,
            centre[1] - half + k as f32 * step,
        );
        ObstacleVertex {
            position: [x, terrain.height(x, z), z],
            normal: terrain.normal(x, z, 0.5 * step).to_array(),
            albedo: SOIL.to_array(),
        }
    };
    let row: Vec<Vec<ObstacleVertex>> = (0..=QUADS)
        .map(|k| (0..=QUADS).map(|i| corner(i, k)).collect())
        .collect();
    let mut out = Vec::with_capacity(6 * QUADS * QUADS);
    for k in 0..QUADS {
        for i in 0..QUADS {
            let (a, b, c, d) = (row[k][i], row[k][i + 1], row[k + 1][i + 1], row[k + 1][i]);
            // Counter-clockwise seen from above (+y): a, d, c and a, c, b.
            out.extend([a, d, c, a, c, b]);
        }
    }
    out
}

/// The lowest ground under the grass's box and what it can shade (the
/// shadows the cull pass follows down to it; 0 on flat ground).
pub fn lowest(scene: &Scene) -> f32 {
    let terrain = scene.ground.terrain();
    if terrain.is_flat() {
        return 0.0;
    }
    let c = scene.grass_center();
    let half = half_side(scene.ground.half_extent);
    terrain
        .range_over(
            [c.x - half, c.z - half],
            [c.x + half, c.z + half],
            half / 64.0,
        )
        .0
        .min(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::terrain::Hill;

    #[test]
    fn the_mesh_lies_on_the_ground_and_faces_up() {
        let terrain = Terrain {
            hills: vec![Hill {
                center: [1.0, 2.0],
                height: 3.0,
                half_width: 4.0,
            }],
            ..Terrain::default()
        };
        let tris = grid(&terrain, [0.0, 0.0], 20.0);
        assert_eq!(tris.len(), 6 * QUADS * QUADS);
        for t in tris.chunks(3) {
            let p: Vec<Vec3> = t.iter().map(|v| Vec3::from(v.position)).collect();
            let up = (p[1] - p[0]).cross(p[2] - p[0]);
            assert!(up.y > 0.0, "{p:?}");
            for (q, v) in p.iter().zip(t) {
                assert_eq!(q.y, terrain.height(q.x, q.z));
                assert!(Vec3::from(v.normal).y > 0.0);
            }
        }
    }
}
