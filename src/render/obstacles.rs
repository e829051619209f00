//! The obstacles the wind meets (paper Fig. 13): boxes, spheres and upright
//! cylinders, drawn as triangle meshes made once on the CPU, shaded in the
//! colour pass and cast into the shadow map (glsl/obstacle/). The same
//! shapes the wind solver voxelises (`model::wind::Obstacle`), so what the
//! picture shows is what blocks the air.
//!
//! The colliders that press the grass (`model::collider::Collider`) are drawn
//! the same way: each a mesh about its own reference point, placed each
//! frame where it is at the frame's simulated time (and a rolling ball
//! turned as it has rolled) by a model matrix in push constants.

use std::ops::Range;

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::Result;
use crate::gpu::{Access, Buffer, CommandPool, Gpu, Pipeline, Recording};
use crate::model::contact::{Collider, ColliderKind};
use crate::model::wind::Obstacle;

/// One corner of an obstacle's triangle list (`obstacle.vert`'s inputs).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ObstacleVertex {
    pub position: [f32; 3],
    /// Outward unit normal.
    pub normal: [f32; 3],
    /// Linear RGB reflectance.
    pub albedo: [f32; 3],
}

/// Segments around a sphere's or cylinder's axis, and a sphere's rings.
const AROUND: usize = 40;
const RINGS: usize = 20;

/// A weathered wall, a grey boulder, a wooden post.
const BOX_ALBEDO: Vec3 = Vec3::new(0.24, 0.23, 0.21);
const SPHERE_ALBEDO: Vec3 = Vec3::new(0.2, 0.2, 0.19);
const CYLINDER_ALBEDO: Vec3 = Vec3::new(0.16, 0.1, 0.055);
/// A ball's gores, alternating (so its roll shows), and a walker's coat.
const BALL_ALBEDO: [Vec3; 2] = [Vec3::new(0.6, 0.05, 0.03), Vec3::new(0.78, 0.76, 0.7)];
const BALL_GORES: usize = 8;
const CAPSULE_ALBEDO: Vec3 = Vec3::new(0.07, 0.1, 0.22);

/// The push constants of the obstacle pipelines: where a mesh's own frame
/// lies in the world.
pub use crate::interface::Placement;

/// The placement of a mesh whose frame is `model` (its frame to world).
pub fn placement(model: Mat4) -> Placement {
    Placement {
        model: model.to_cols_array_2d(),
    }
}

fn vertex(p: Vec3, n: Vec3, albedo: Vec3) -> ObstacleVertex {
    ObstacleVertex {
        position: p.to_array(),
        normal: n.to_array(),
        albedo: albedo.to_array(),
    }
}

/// A quad a, b, c, d (counter-clockwise seen from outside) as two triangles.
fn quad(out: &mut Vec<ObstacleVertex>, [a, b, c, d]: [Vec3; 4], n: Vec3, albedo: Vec3) {
    for p in [a, b, c, a, c, d] {
        out.push(vertex(p, n, albedo));
    }
}

/// The point on the unit sphere at azimuth i / AROUND and polar ring j / RINGS.
fn on_sphere(i: usize, j: usize) -> Vec3 {
    let (azimuth, polar) = (
        i as f32 / AROUND as f32 * std::f32::consts::TAU,
        j as f32 / RINGS as f32 * std::f32::consts::PI,
    );
    Vec3::new(
        polar.sin() * azimuth.cos(),
        polar.cos(),
        polar.sin() * azimuth.sin(),
    )
}

/// The triangles of every obstacle, each face with its outward normal.
pub fn mesh(obstacles: &[Obstacle]) -> Vec<ObstacleVertex> {
    let mut out = Vec::new();
    for o in obstacles {
        match *o {
            Obstacle::Box { min, max } => {
                let c = |x: bool, y: bool, z: bool| {
                    Vec3::new(
                        if x { max.x } else { min.x },
                        if y { max.y } else { min.y },
                        if z { max.z } else { min.z },
                    )
                };
                let (f, t) = (false, true);
                let faces = [
                    ([c(t, f, f), c(t, t, f), c(t, t, t), c(t, f, t)], Vec3::X),
                    (
                        [c(f, f, f), c(f, f, t), c(f, t, t), c(f, t, f)],
                        Vec3::NEG_X,
                    ),
                    ([c(f, t, f), c(f, t, t), c(t, t, t), c(t, t, f)], Vec3::Y),
                    (
                        [c(f, f, f), c(t, f, f), c(t, f, t), c(f, f, t)],
                        Vec3::NEG_Y,
                    ),
                    ([c(f, f, t), c(t, f, t), c(t, t, t), c(f, t, t)], Vec3::Z),
                    (
                        [c(f, f, f), c(f, t, f), c(t, t, f), c(t, f, f)],
                        Vec3::NEG_Z,
                    ),
                ];
                for (corners, n) in faces {
                    quad(&mut out, corners, n, BOX_ALBEDO);
                }
            }
            Obstacle::Sphere { center, radius } => {
                for j in 0..RINGS {
                    for i in 0..AROUND {
                        let corners = [(i, j), (i, j + 1), (i + 1, j + 1), (i + 1, j)];
                        for k in [0, 2, 1, 0, 3, 2] {
                            let (a, b) = corners[k];
                            let n = on_sphere(a, b);
                            out.push(vertex(center + n * radius, n, SPHERE_ALBEDO));
                        }
                    }
                }
            }
            Obstacle::Cylinder {
                base,
                radius,
                height,
            } => {
                let rim = |i: usize| on_sphere(i, RINGS / 2);
                let top = base + Vec3::Y * height;
                for i in 0..AROUND {
                    let (a, b) = (rim(i), rim(i + 1));
                    let side = [
                        base + a * radius,
                        top + a * radius,
                        top + b * radius,
                        base + b * radius,
                    ];
                    for (k, p) in [0, 1, 2, 0, 2, 3].map(|k| (k, side[k])) {
                        let n = if k == 0 || k == 1 { a } else { b };
                        out.push(vertex(p, n, CYLINDER_ALBEDO));
                    }
                    for p in [top, top + b * radius, top + a * radius] {
                        out.push(vertex(p, Vec3::Y, CYLINDER_ALBEDO));
                    }
                }
            }
        }
    }
    out
}

/// Quads between rings `j` and `j + 1` of a sphere of `radius` about
/// `centre(j)` (a capsule's caps have two centres), coloured by
/// `albedo(i)` for the segment i around.
fn rings(
    out: &mut Vec<ObstacleVertex>,
    radius: f32,
    centre: impl Fn(usize) -> Vec3,
    albedo: impl Fn(usize) -> Vec3,
) {
    for j in 0..RINGS {
        let c = centre(j);
        for i in 0..AROUND {
            let corners = [(i, j), (i, j + 1), (i + 1, j + 1), (i + 1, j)];
            for k in [0, 2, 1, 0, 3, 2] {
                let (a, b) = corners[k];
                let n = on_sphere(a, b);
                out.push(vertex(c + n * radius, n, albedo(i)));
            }
        }
    }
}

/// A collider's triangles about its reference point (`Collider::motion_at`):
/// a ball about its centre, in gores that show its roll; an upright
/// capsule from its lowest point up, two half balls and the tube between.
pub fn collider_mesh(collider: &Collider) -> Vec<ObstacleVertex> {
    let mut out = Vec::new();
    let r = collider.radius;
    match collider.kind {
        ColliderKind::Sphere => rings(
            &mut out,
            r,
            |_| Vec3::ZERO,
            |i| BALL_ALBEDO[i * BALL_GORES / AROUND % 2],
        ),
        ColliderKind::Capsule => {
            let (low, high) = (Vec3::Y * r, Vec3::Y * (collider.height - r).max(r));
            // Rings 0..RINGS/2 are the upper half of a ball.
            let centre = |j: usize| if j < RINGS / 2 { high } else { low };
            rings(&mut out, r, centre, |_| CAPSULE_ALBEDO);
            for i in 0..AROUND {
                let (a, b) = (on_sphere(i, RINGS / 2), on_sphere(i + 1, RINGS / 2));
                let side = [low + a * r, high + a * r, high + b * r, low + b * r];
                for k in [0, 1, 2, 0, 2, 3] {
                    let n = if k < 2 { a } else { b };
                    out.push(vertex(side[k], n, CAPSULE_ALBEDO));
                }
            }
        }
    }
    out
}

/// Where `collider` is drawn at time t: at its reference point, turned as
/// it has rolled.
pub fn collider_placement(collider: &Collider, t: f32) -> Placement {
    let (at, _, _) = collider.motion_at(t);
    placement(Mat4::from_rotation_translation(
        collider.orientation_at(t),
        at,
    ))
}

/// The obstacles' and colliders' triangles on the GPU; nothing when the
/// scene has neither.
pub struct ObstacleMeshes {
    vertices: Option<Buffer>,
    /// The obstacles' triangles (in world space), first in the buffer;
    /// kept to rebuild the buffer when the colliders change shape.
    fixed: Vec<ObstacleVertex>,
    /// The colliders drawn, and each one's vertices in the buffer (in its
    /// own frame) and where it is drawn this frame.
    colliders: Vec<Collider>,
    placed: Vec<(Range<u32>, Placement)>,
}

impl ObstacleMeshes {
    /// The obstacles' and colliders' meshes.
    pub fn new(
        gpu: &Gpu,
        commands: &CommandPool,
        obstacles: &[Obstacle],
        colliders: &[Collider],
    ) -> Result<Self> {
        Self::build(gpu, commands, mesh(obstacles), colliders)
    }

    fn build(
        gpu: &Gpu,
        commands: &CommandPool,
        fixed: Vec<ObstacleVertex>,
        colliders: &[Collider],
    ) -> Result<Self> {
        let mut triangles = fixed.clone();
        let mut placed = Vec::with_capacity(colliders.len());
        for c in colliders {
            let first = triangles.len() as u32;
            triangles.extend(collider_mesh(c));
            placed.push((first..triangles.len() as u32, collider_placement(c, 0.0)));
        }
        let vertices = if triangles.is_empty() {
            None
        } else {
            Some(Buffer::with_data(
                gpu,
                commands,
                "obstacle and collider triangles (vertex buffer)",
                bytemuck::cast_slice(&triangles),
                vk::BufferUsageFlags::VERTEX_BUFFER,
                Access::VERTEX_INPUT,
            )?)
        };
        Ok(Self {
            vertices,
            fixed,
            colliders: colliders.to_vec(),
            placed,
        })
    }

    /// Draws `colliders` from now on: where they have the shapes of those
    /// drawn so far, only their motion changes; else their meshes are
    /// made anew (uploads and waits: call between submissions).
    pub fn set_colliders(
        &mut self,
        gpu: &Gpu,
        commands: &CommandPool,
        colliders: &[Collider],
    ) -> Result<()> {
        let same_shape = |a: &Collider, b: &Collider| {
            (a.kind, a.radius, a.height) == (b.kind, b.radius, b.height)
        };
        let reshaped = colliders.len() != self.colliders.len()
            || colliders
                .iter()
                .zip(&self.colliders)
                .any(|(new, old)| !same_shape(new, old));
        if reshaped {
            let fixed = std::mem::take(&mut self.fixed);
            // The old buffer goes once the new one is made (no frame is in
            // flight between submissions).
            *self = Self::build(gpu, commands, fixed, colliders)?;
        } else {
            self.colliders = colliders.to_vec();
        }
        Ok(())
    }

    /// The colliders drawn.
    pub fn colliders(&self) -> &[Collider] {
        &self.colliders
    }

    /// Places the colliders where they are at simulated time `t` (s), for
    /// the frames recorded from now on.
    pub fn place_colliders(&mut self, t: f32) {
        for ((_, placement), collider) in self.placed.iter_mut().zip(&self.colliders) {
            *placement = collider_placement(collider, t);
        }
    }

    /// Draws every obstacle and collider with `pipeline` (the colour
    /// pass's, or the shadow pass's depth-only one), its set already bound.
    pub fn draw(&self, rec: &Recording, pipeline: &Pipeline) {
        if let Some(vertices) = &self.vertices {
            rec.bind_pipeline(pipeline);
            rec.bind_vertex_buffer(vertices);
            if !self.fixed.is_empty() {
                rec.push_constants(pipeline, &placement(Mat4::IDENTITY));
                rec.draw_range(0..self.fixed.len() as u32);
            }
            for (range, placement) in &self.placed {
                rec.push_constants(pipeline, placement);
                rec.draw_range(range.clone());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every triangle winds counter-clockwise seen from outside: its
    /// geometric normal agrees with its vertices' normals and points away
    /// from the shape's inside.
    #[test]
    fn triangles_face_outward_and_lie_on_their_shape() {
        let shapes = [
            Obstacle::Box {
                min: Vec3::new(-2.4, 0.0, -2.6),
                max: Vec3::new(-2.0, 1.2, -0.6),
            },
            Obstacle::Sphere {
                center: Vec3::new(1.0, 0.0, 1.0),
                radius: 0.8,
            },
            Obstacle::Cylinder {
                base: Vec3::new(-1.0, 0.0, 2.4),
                radius: 0.25,
                height: 2.0,
            },
        ];
        for shape in shapes {
            let tris = mesh(&[shape]);
            assert!(!tris.is_empty() && tris.len() % 3 == 0);
            let inside = match shape {
                Obstacle::Box { min, max } => (min + max) / 2.0,
                Obstacle::Sphere { center, .. } => center,
                Obstacle::Cylinder { base, height, .. } => base + Vec3::Y * height / 2.0,
            };
            for t in tris.chunks(3) {
                let p: Vec<Vec3> = t.iter().map(|v| Vec3::from(v.position)).collect();
                let cross = (p[1] - p[0]).cross(p[2] - p[0]);
                if cross.length() < 1e-6 {
                    continue; // a sphere's pole: a sliver, nothing to see
                }
                let centre = (p[0] + p[1] + p[2]) / 3.0;
                let n = Vec3::from(t[0].normal);
                assert!(
                    cross.dot(n) > 0.0,
                    "{shape:?}: a triangle winds inward: {p:?} {n} {cross}"
                );
                assert!(cross.dot(centre - inside) > 0.0, "{shape:?}: faces inside");
                assert!((n.length() - 1.0).abs() < 1e-5);
                for q in &p {
                    // Every corner lies on the surface the wind sees.
                    let grown = match shape {
                        Obstacle::Box { min, max } => Obstacle::Box {
                            min: min - 1e-4,
                            max: max + 1e-4,
                        },
                        Obstacle::Sphere { center, radius } => Obstacle::Sphere {
                            center,
                            radius: radius + 1e-4,
                        },
                        Obstacle::Cylinder {
                            base,
                            radius,
                            height,
                        } => Obstacle::Cylinder {
                            base: base - Vec3::Y * 1e-4,
                            radius: radius + 1e-4,
                            height: height + 2e-4,
                        },
                    };
                    assert!(grown.contains(*q), "{shape:?}: corner {q} off the shape");
                }
            }
        }
        assert!(mesh(&[]).is_empty());
    }

    /// A collider's mesh, placed where it is at some time, lies on the
    /// surface the contact sees (`ColliderState::distance` 0) and faces
    /// out; a rolling ball's gores turn with it, its surface does not move.
    #[test]
    fn collider_meshes_lie_on_the_surface_the_grass_meets() {
        let path = vec![Vec3::new(-2.0, 0.4, 0.0), Vec3::new(2.0, 0.4, 1.0)];
        let ball = Collider {
            kind: ColliderKind::Sphere,
            radius: 0.4,
            height: 0.0,
            position: Vec3::ZERO,
            path: path.clone(),
            path_speed: 1.2,
            closed: true,
            roll: true,
            ..Default::default()
        };
        let walker = Collider {
            kind: ColliderKind::Capsule,
            radius: 0.25,
            height: 1.7,
            roll: false,
            ..ball.clone()
        };
        for c in [ball, walker] {
            let tris = collider_mesh(&c);
            assert!(!tris.is_empty() && tris.len() % 3 == 0);
            for t in [0.0, 1.3, 5.0] {
                let model = Mat4::from_cols_array_2d(&collider_placement(&c, t).model);
                let state = c.at(t);
                let inside = (state.a + state.b) / 2.0;
                for tri in tris.chunks(3) {
                    let p: Vec<Vec3> = tri
                        .iter()
                        .map(|v| model.transform_point3(Vec3::from(v.position)))
                        .collect();
                    for q in &p {
                        let (d, _) = state.distance(*q);
                        assert!(
                            d.abs() < 1e-4,
                            "{:?} at {t} s: corner {q} {d} m off",
                            c.kind
                        );
                    }
                    let cross = (p[1] - p[0]).cross(p[2] - p[0]);
                    if cross.length() < 1e-6 {
                        continue;
                    }
                    let n = model.transform_vector3(Vec3::from(tri[0].normal));
                    assert!(cross.dot(n) > 0.0 && cross.dot(p[0] - inside) > 0.0);
                }
            }
        }
    }
}
