//! A collider (ours; docs/physics.md, "Colliders"): a sphere or an upright
//! capsule moving through the meadow like a wind source, at a position or
//! along a path; where it is at an instant (`ColliderState`), and its GPU
//! record. How it presses the grass is src/model/contact.rs.

use glam::{Quat, Vec3};

use crate::model::path::{along_path, MAX_PATH_POINTS};
use crate::model::terrain::Terrain;

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

    /// How far it reaches into `terrain` at its deepest, at its position
    /// or anywhere along its path (0 or less: clear of the ground by that
    /// much), and where its lowest cap's centre is then. Upright, its
    /// surface over a point d from its axis lies sqrt(r^2 - d^2) under
    /// that centre (a sphere's centre, a capsule's `a`), so the depth is
    /// the largest h(q) + sqrt(r^2 - d^2) - centre.y over ground points q
    /// under it, sampled on rings: on flat ground exactly `-lowest()`.
    pub fn depth_in(&self, terrain: &Terrain) -> (f32, Vec3) {
        let lift = match self.kind {
            ColliderKind::Sphere => 0.0,
            ColliderKind::Capsule => self.radius,
        };
        let r = self.radius;
        let depth_at = |p: Vec3| {
            let centre = p + Vec3::Y * lift;
            let (rings, around) = (8, 24);
            let mut deepest = terrain.height(centre.x, centre.z) + r - centre.y;
            for k in 1..=rings {
                let d = r * k as f32 / rings as f32;
                let under = (r * r - d * d).max(0.0).sqrt();
                for a in 0..around {
                    let (s, c) = (a as f32 * std::f32::consts::TAU / around as f32).sin_cos();
                    let (x, z) = (centre.x + d * c, centre.z + d * s);
                    deepest = deepest.max(terrain.height(x, z) + under - centre.y);
                }
            }
            (deepest, centre)
        };
        let deepest = |a: (f32, Vec3), b: (f32, Vec3)| if b.0 > a.0 { b } else { a };
        if self.path.is_empty() {
            return depth_at(self.position);
        }
        let n = self.path.len();
        let segments = if self.closed && n > 1 { n } else { n - 1 };
        // Along each stretch every half radius (at most 512 a stretch): a
        // rise between two waypoints counts as much as one at them.
        let step = (0.5 * r).max(0.05);
        let mut worst = depth_at(self.path[0]);
        for i in 0..segments {
            let (p, q) = (self.path[i], self.path[(i + 1) % n]);
            let m = ((p.distance(q) / step).ceil() as usize).clamp(1, 512);
            for j in 1..=m {
                worst = deepest(worst, depth_at(p.lerp(q, j as f32 / m as f32)));
            }
        }
        worst
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
            position: c.position.to_array(),
            radius: c.radius,
            capsule: (c.kind == ColliderKind::Capsule) as u32,
            height: c.height,
            path_points: c.path.len().min(MAX_PATH_POINTS) as u32,
            path_speed: c.path_speed,
            closed: c.closed as u32,
            sets_off: c.start,
            path,
            ..Self::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    fn ball(path: Vec<Vec3>, closed: bool) -> Collider {
        Collider {
            kind: ColliderKind::Sphere,
            radius: 0.3,
            height: 0.0,
            position: Vec3::ZERO,
            path,
            path_speed: 2.0,
            closed,
            roll: false,
            ..Default::default()
        }
    }

    /// The turn of a rolling ball, against an integration of
    /// dq/dt = (omega / 2) q with omega = (up x v) / radius, the rolling
    /// condition, in 1 ms steps over two and a half laps of a closed path
    /// (the whole laps taken as one rotation) and past the end of an open
    /// one (it stops turning when it stops).
    #[test]
    fn a_rolling_ball_turns_as_rolling_without_slipping_says() {
        let path = vec![
            Vec3::new(0.0, 0.3, 0.0),
            Vec3::new(3.0, 0.3, 0.0),
            Vec3::new(3.0, 0.3, 2.0),
            Vec3::new(1.0, 0.3, 3.0),
        ];
        for closed in [true, false] {
            let mut b = ball(path.clone(), closed);
            b.roll = true;
            let (h, end) = (1e-3f32, if closed { 6.5 } else { 5.0 });
            let mut q = Quat::IDENTITY;
            let mut t = 0.0f32;
            let mut worst = 0.0f32;
            for step in 0..(end / h) as usize {
                let (_, v, _) = b.motion_at(t + h / 2.0);
                let omega = Vec3::Y.cross(v) / b.radius;
                let len = omega.length() * h;
                if len > 0.0 {
                    q = (Quat::from_axis_angle(omega / omega.length(), len) * q).normalize();
                }
                t = (step + 1) as f32 * h;
                let expected = b.orientation_at(t);
                worst = worst.max(expected.angle_between(q));
            }
            // 6.5 s is 13 m, over two laps of 5.9 m.
            assert!(
                worst < 0.01,
                "closed {closed}: {worst} rad from the integrated turn"
            );
        }
        // Not rolling: never turned.
        let still = ball(path, true);
        assert_eq!(still.orientation_at(3.0), Quat::IDENTITY);
    }

    #[test]
    fn an_open_path_is_travelled_once_and_a_closed_one_round() {
        let square = vec![
            Vec3::new(0.0, 0.3, 0.0),
            Vec3::new(4.0, 0.3, 0.0),
            Vec3::new(4.0, 0.3, 4.0),
        ];
        let open = ball(square.clone(), false);
        // 8 m of path at 2 m/s: half way along the second leg at 3 s.
        let (p, v, s) = open.motion_at(3.0);
        assert!(p.distance(Vec3::new(4.0, 0.3, 2.0)) < 1e-5, "{p}");
        assert!(v.distance(Vec3::new(0.0, 0.0, 2.0)) < 1e-5, "{v}");
        assert!((s - 6.0).abs() < 1e-5);
        let (p, v, _) = open.motion_at(10.0);
        assert!(p.distance(square[2]) < 1e-5 && v == Vec3::ZERO, "{p} {v}");
        // Closed: 4 + 4 + 4 sqrt 2 m round; at 6 s (12 m) 4 m down the way back.
        let closed = ball(square.clone(), true);
        let total = 8.0 + 32f32.sqrt();
        let (p, v, _) = closed.motion_at(6.0);
        let back = (square[0] - square[2]).normalize();
        let expected = square[2] + back * (12.0 - 8.0);
        assert!(p.distance(expected) < 1e-4, "{p} {expected}");
        assert!(v.distance(back * 2.0) < 1e-5);
        let (p, _, _) = closed.motion_at(total / 2.0 + 0.5);
        assert!(p.distance(square[0] + Vec3::X) < 1e-4, "{p}");
    }

    /// `start` holds a collider at its first point until then, and a
    /// ball set off again from where another stretch left it (`turned`, as
    /// the viewer's steered ball) turns on from that turn: two stretches
    /// chained give the turn of one path through both.
    #[test]
    fn a_collider_waits_for_its_start_and_carries_its_turn_on() {
        let mut late = ball(
            vec![Vec3::new(0.0, 0.3, 0.0), Vec3::new(4.0, 0.3, 0.0)],
            false,
        );
        late.start = 1.5;
        assert_eq!(
            late.motion_at(1.0),
            (Vec3::new(0.0, 0.3, 0.0), Vec3::ZERO, 0.0)
        );
        let (p, v, _) = late.motion_at(2.0);
        assert!(
            p.distance(Vec3::new(1.0, 0.3, 0.0)) < 1e-5 && v == Vec3::X * 2.0,
            "{p} {v}"
        );

        let corner = [
            Vec3::new(0.0, 0.3, 0.0),
            Vec3::new(2.0, 0.3, 0.0),
            Vec3::new(2.0, 0.3, 3.0),
        ];
        let mut whole = ball(corner.to_vec(), false);
        whole.roll = true;
        let mut first = ball(corner[..2].to_vec(), false);
        first.roll = true;
        let second = Collider {
            path: corner[1..].to_vec(),
            start: 1.0, // 2 m at 2 m/s
            turned: first.orientation_at(1.0),
            ..first.clone()
        };
        for t in [1.2f32, 2.0, 2.5, 4.0] {
            let (a, b) = (whole.orientation_at(t), second.orientation_at(t));
            assert!(a.angle_between(b) < 1e-4, "t {t}: {a} vs {b}");
            assert!(whole.motion_at(t).0.distance(second.motion_at(t).0) < 1e-5);
        }
        // 2 m over a 0.3 m radius: 6.67 rad, 0.38 rad from where it began.
        assert!(second.turned.angle_between(Quat::IDENTITY) > 0.3);
    }

    #[test]
    fn a_capsule_distance_is_to_its_axis_and_a_sphere_to_its_centre() {
        let walker = Collider {
            kind: ColliderKind::Capsule,
            radius: 0.25,
            height: 1.8,
            position: Vec3::new(1.0, 0.0, 0.0),
            ..ball(Vec::new(), false)
        }
        .at(0.0);
        let (d, n) = walker.distance(Vec3::new(2.0, 1.0, 0.0));
        assert!((d - 0.75).abs() < 1e-6 && n.distance(Vec3::X) < 1e-6);
        // Below the lower cap's centre: distance to that centre.
        let (d, n) = walker.distance(Vec3::new(1.0, 0.0, 0.0));
        assert!(d.abs() < 1e-6 && n.distance(-Vec3::Y) < 1e-6, "{d} {n}");
        let (d, _) = walker.distance(Vec3::new(1.0, 1.8, 0.0));
        assert!(d.abs() < 1e-6, "top {d}");
        let sphere = ball(Vec::new(), false);
        assert_eq!(sphere.depth_in(&Terrain::default()).0, 0.3);
        let (d, _) = sphere.at(0.0).distance(Vec3::new(0.0, 0.5, 0.0));
        assert!((d - 0.2).abs() < 1e-6);
    }

    /// The depth in the ground is the hill's, not y's: a ball resting on
    /// a hill's top is clear, one at the same height over its flank sinks
    /// in uphill, a path between two clear keys over the crest is caught
    /// between them, and a capsule in a hollow under y = 0 is clear.
    #[test]
    fn the_depth_in_the_ground_follows_the_terrain_along_the_path() {
        use crate::model::terrain::Hill;
        let hill = Terrain {
            hills: vec![Hill {
                center: [0.0, 0.0],
                height: 2.0,
                half_width: 2.5,
            }],
            ..Terrain::default()
        };
        let at = |x: f32, lift: f32| Vec3::new(x, hill.height(x, 0.0) + lift, 0.0);
        let on_top = Collider {
            position: at(0.0, 0.3),
            ..ball(Vec::new(), false)
        };
        assert!(
            on_top.depth_in(&hill).0.abs() < 1e-6,
            "{:?}",
            on_top.depth_in(&hill)
        );
        let on_flank = Collider {
            position: at(2.5, 0.3),
            ..ball(Vec::new(), false)
        };
        let (depth, _) = on_flank.depth_in(&hill);
        assert!(depth > 0.02, "a ball on the flank reaches {depth} m in");
        let over_the_crest = ball(vec![at(-6.0, 0.5), at(6.0, 0.5)], false);
        assert!(at(-6.0, 0.5).y < 1.0);
        let (depth, centre) = over_the_crest.depth_in(&hill);
        assert!(depth > 1.0 && centre.x.abs() < 0.5, "{depth} at {centre}");
        let hollow = Terrain {
            hills: vec![Hill {
                height: -2.0,
                ..hill.hills[0]
            }],
            ..Terrain::default()
        };
        let walker = Collider {
            kind: ColliderKind::Capsule,
            radius: 0.25,
            height: 1.8,
            position: Vec3::new(0.0, -1.9, 0.0),
            ..ball(Vec::new(), false)
        };
        let (depth, _) = walker.depth_in(&hollow);
        assert!((-0.11..0.0).contains(&depth), "{depth}");
    }
}
