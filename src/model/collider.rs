//! A collider (ours; docs/physics.md, "Colliders"): a sphere or an upright
//! capsule moving through the meadow like a wind source, at a position or
//! along a path; where it is at an instant (`ColliderState`), and its GPU
//! record. How it presses the grass is src/model/contact.rs.

use glam::{Quat, Vec3};

use crate::model::path::{along_path, MAX_PATH_POINTS};

/// A collider's shape.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ColliderKind {
    /// A ball; `position` is its centre.
    #[default]
    Sphere,
    /// An upright capsule (a walker, a post); `position` is its lowest
    /// point, `height` its whole height, caps included.
    Capsule,
}

/// A thing that moves through the meadow (`[[collider]]` in a scene file),
/// moving like a wind source: at `position`, or along `path`.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Collider {
    pub kind: ColliderKind,
    /// Radius (m).
    pub radius: f32,
    /// A capsule's whole height (m), at least twice its radius.
    #[serde(default)]
    pub height: f32,
    /// Where it stands when it has no path.
    #[serde(default)]
    pub position: Vec3,
    /// Up to 8 waypoints it moves through at `path_speed`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub path: Vec<Vec3>,
    /// Speed along the path (m/s).
    #[serde(default)]
    pub path_speed: f32,
    /// Whether the path closes (the last point leads back to the first,
    /// round and round); an open path is travelled once and it stops at
    /// its end.
    #[serde(default)]
    pub closed: bool,
    /// A sphere turns as it travels (drawn; the contact is the same).
    #[serde(default)]
    pub roll: bool,
    /// The simulated time (s) it sets off along its path; until then it
    /// waits at the path's first point.
    #[serde(default)]
    pub start: f32,
    /// How a rolling sphere is turned when it sets off (drawn only; not a
    /// scene key): the viewer's steered ball carries its turn from one
    /// stretch to the next.
    #[serde(skip)]
    pub turned: Quat,
}

/// A collider at one instant: the segment a..b swept by `radius` (a == b
/// for a sphere) and the velocity of its centre.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ColliderState {
    pub a: Vec3,
    pub b: Vec3,
    pub radius: f32,
    pub velocity: Vec3,
}

impl Collider {
    /// Its reference point (a sphere's centre, a capsule's lowest point),
    /// velocity and distance travelled at time t.
    pub fn motion_at(&self, t: f32) -> (Vec3, Vec3, f32) {
        if t < self.start {
            // Waiting to set off: still, at the first point.
            let (at, _, _) = along_path(&self.path, 0.0, self.closed, 0.0, self.position);
            return (at, Vec3::ZERO, 0.0);
        }
        along_path(
            &self.path,
            self.path_speed,
            self.closed,
            t - self.start,
            self.position,
        )
    }

    /// The collider at time t.
    pub fn at(&self, t: f32) -> ColliderState {
        let (p, velocity, _) = self.motion_at(t);
        let (a, b) = match self.kind {
            ColliderKind::Sphere => (p, p),
            ColliderKind::Capsule => (
                p + Vec3::Y * self.radius,
                p + Vec3::Y * (self.height - self.radius).max(self.radius),
            ),
        };
        ColliderState {
            a,
            b,
            radius: self.radius,
            velocity,
        }
    }

    /// How a rolling sphere is turned at time t (`turned` for anything
    /// that does not roll): rolling without slipping on level ground, each
    /// stretch of its path turns it about the horizontal axis across its
    /// travel (up x direction) by the ground distance over its radius, so
    /// the point touching the ground stands still. Drawn only; the contact
    /// sees a sphere, whatever its turn.
    pub fn orientation_at(&self, t: f32) -> Quat {
        (self.turn_along_path(t) * self.turned).normalize()
    }

    /// The turn since it set off: `orientation_at` without `turned`.
    fn turn_along_path(&self, t: f32) -> Quat {
        let n = self.path.len();
        if !self.roll || self.kind != ColliderKind::Sphere || n < 2 || self.radius <= 0.0 {
            return Quat::IDENTITY;
        }
        let (_, _, travelled) = self.motion_at(t);
        let segments = if self.closed { n } else { n - 1 };
        let stretch = |i: usize| (self.path[i], self.path[(i + 1) % n]);
        let turn = |(p, q): (Vec3, Vec3), distance: f32| {
            let ground = Vec3::new(q.x - p.x, 0.0, q.z - p.z);
            let along = ground.length();
            if along <= 0.0 {
                return Quat::IDENTITY; // straight up or down: nothing rolls
            }
            // The ground covered over this much of the stretch's length.
            let covered = distance * along / p.distance(q);
            Quat::from_axis_angle(Vec3::Y.cross(ground) / along, covered / self.radius)
        };
        let lap: f32 = (0..segments)
            .map(|i| {
                let (p, q) = stretch(i);
                p.distance(q)
            })
            .sum();
        if lap <= 0.0 {
            return Quat::IDENTITY;
        }
        // Whole laps of a closed path first: one lap's turn, taken as many
        // times, as one rotation about its axis. (An open path's travel
        // stops at its end: `along_path` never says more than a lap.)
        let (mut q, mut left) = (Quat::IDENTITY, travelled);
        if self.closed && left >= lap {
            let laps = (left / lap).floor();
            let one = (0..segments).fold(Quat::IDENTITY, |q, i| {
                let s = stretch(i);
                (turn(s, s.0.distance(s.1)) * q).normalize()
            });
            let (axis, angle) = one.to_axis_angle();
            q = Quat::from_axis_angle(axis, angle * laps);
            left -= laps * lap;
        }
        for i in 0..segments {
            let s = stretch(i);
            let len = s.0.distance(s.1);
            q = (turn(s, len.min(left)) * q).normalize();
            left -= len;
            if left <= 0.0 {
                break;
            }
        }
        q
    }

    /// The lowest height it reaches, at its position or any waypoint.
    pub fn lowest(&self) -> f32 {
        let lift = match self.kind {
            ColliderKind::Sphere => -self.radius,
            ColliderKind::Capsule => 0.0,
        };
        let points = if self.path.is_empty() {
            std::slice::from_ref(&self.position)
        } else {
            &self.path[..]
        };
        points
            .iter()
            .map(|p| p.y + lift)
            .fold(f32::INFINITY, f32::min)
    }
}

impl ColliderState {
    /// Signed distance from `p` to the surface (negative inside) and the
    /// outward normal there.
    pub fn distance(&self, p: Vec3) -> (f32, Vec3) {
        let ab = self.b - self.a;
        let len2 = ab.dot(ab);
        let t = if len2 > 0.0 {
            ((p - self.a).dot(ab) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let off = p - (self.a + ab * t);
        let l = off.length();
        let n = if l > 1e-12 { off / l } else { Vec3::Y };
        (l - self.radius, n)
    }

    /// Whether a blade rooted at `root` and `reach` long could touch it.
    pub fn near(&self, root: Vec3, reach: f32) -> bool {
        self.distance(root).0 < reach
    }
}

/// The GPU record of one collider (src/interface/defs.rs).
pub use crate::interface::GpuCollider;

impl From<&Collider> for GpuCollider {
    fn from(c: &Collider) -> Self {
        let mut path = [[0.0; 4]; MAX_PATH_POINTS];
        for (slot, p) in path.iter_mut().zip(&c.path) {
            *slot = p.extend(0.0).to_array();
        }
        Self {
            position_radius: c.position.extend(c.radius).to_array(),
            shape: [
                match c.kind {
                    ColliderKind::Sphere => 0.0,
                    ColliderKind::Capsule => 1.0,
                },
                c.height,
                c.path.len().min(MAX_PATH_POINTS) as f32,
                c.path_speed,
            ],
            flags: [c.closed as u32 as f32, c.start, 0.0, 0.0],
            path,
        }
    }
}
