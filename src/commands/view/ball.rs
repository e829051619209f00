//! The viewer's ball: B brings a ball onto the ground where the middle of
//! the window looks (B again takes it away); a right click on the ground
//! rolls it there. It is pushed as a hand would push it: it speeds up at
//! `ACCELERATION` up to `MAX_SPEED`, slows down in time to stop on the
//! point, and stops. It presses the grass, pushes the air and is drawn as
//! any collider is (src/model/contact.rs): each frame's stretch of its motion
//! goes to the GPU as a collider whose path is that stretch, setting off at
//! the frame's first simulated instant (`Collider::start`) and turned as the
//! last stretch left it (`Collider::turned`), so the grass steps inside the
//! frame see it move as it is integrated here.

use glam::{Quat, Vec2, Vec3, Vec3Swizzles};

use crate::model::contact::{Collider, ColliderKind};
use crate::model::terrain::Terrain;

/// The ball's radius (m): a football's size and a half.
pub const BALL_RADIUS: f32 = 0.2;
/// How fast a push speeds it up or slows it down (m/s^2).
pub const ACCELERATION: f32 = 2.0;
/// The fastest it is rolled (m/s).
pub const MAX_SPEED: f32 = 2.0;
/// Closer than this to its goal (m), at less than `STOP_SPEED` (m/s), it
/// has arrived and stops.
pub const ARRIVED: f32 = 0.01;
pub const STOP_SPEED: f32 = 0.05;

#[derive(Clone, Debug, PartialEq)]
pub struct Ball {
    /// Its centre, `BALL_RADIUS` above the ground under it.
    pub centre: Vec3,
    pub velocity: Vec3,
    /// How it is turned by its rolling so far.
    pub turned: Quat,
    /// Where it is being rolled to (on the ground), if anywhere.
    pub goal: Option<Vec3>,
    /// The rectangle (x, z) its centre stays in: the wind's domain, less
    /// its radius, so that it pushes air wherever it goes.
    low: Vec2,
    high: Vec2,
    /// The ground it rolls on.
    ground: Terrain,
}

/// What a frame's stretch did: the ball arrived at its goal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrived(pub Vec3);

impl Ball {
    /// A ball at rest on `terrain` at `at` (x, z), kept within the
    /// rectangle `low`..`high` (x, z).
    pub fn new(at: Vec3, low: Vec2, high: Vec2, terrain: Terrain) -> Self {
        let margin = Vec2::splat(BALL_RADIUS);
        let (low, high) = (low + margin, (high - margin).max(low + margin));
        let mut ball = Self {
            centre: Vec3::ZERO,
            velocity: Vec3::ZERO,
            turned: Quat::IDENTITY,
            goal: None,
            low,
            high,
            ground: terrain,
        };
        ball.centre = ball.resting_at(at.xz());
        ball
    }

    /// Its centre resting on the ground at `at` (x, z), kept within its
    /// rectangle.
    fn resting_at(&self, at: Vec2) -> Vec3 {
        let at = at.clamp(self.low, self.high);
        Vec3::new(at.x, self.ground.height(at.x, at.y) + BALL_RADIUS, at.y)
    }

    /// Rolls it to `ground` (kept within its rectangle); returns the goal.
    pub fn roll_to(&mut self, ground: Vec3) -> Vec3 {
        let goal = self.resting_at(ground.xz());
        self.goal = Some(goal);
        goal
    }

    /// The ball from simulated time `from` to `to` (s) as a collider, its
    /// velocity for the stretch chosen at `from`, and the ball moved on to
    /// where it is at `to`. Says when it arrived.
    pub fn stretch(&mut self, from: f32, to: f32) -> (Collider, Option<Arrived>) {
        let h = (to - from).max(0.0);
        if h > 0.0 {
            self.velocity = self.push(h);
        }
        let end = self.resting_at((self.centre + self.velocity * h).xz());
        let moving = end.distance(self.centre) > 1e-6;
        let collider = Collider {
            kind: ColliderKind::Sphere,
            radius: BALL_RADIUS,
            position: self.centre,
            path: if moving {
                vec![self.centre, end]
            } else {
                Vec::new()
            },
            path_speed: if moving {
                end.distance(self.centre) / h
            } else {
                0.0
            },
            // A still ball is the same collider frame after frame (nothing
            // to upload); a moving one sets off at the stretch's start.
            start: if moving { from } else { 0.0 },
            roll: true,
            turned: self.turned,
            ..Default::default()
        };
        self.turned = collider.orientation_at(to);
        if h > 0.0 {
            // Stopped by the rectangle's edge, it keeps no speed across it.
            self.velocity = (end - self.centre) / h;
        }
        self.centre = end;
        let arrived = self.goal.filter(|goal| {
            goal.distance(self.centre) < ARRIVED && self.velocity.length() < STOP_SPEED
        });
        if arrived.is_some() {
            self.goal = None;
            self.velocity = Vec3::ZERO;
        }
        (collider, arrived.map(Arrived))
    }

    /// The velocity for a stretch of `h` seconds: towards the goal as fast
    /// as it may go and still stop on it, in stretches of h; with no goal,
    /// rolling to a stop. The change from the present velocity is at most
    /// `ACCELERATION` x h.
    fn push(&self, h: f32) -> Vec3 {
        let wanted = match self.goal {
            Some(goal) => {
                let to_goal = goal - self.centre;
                let d = to_goal.length();
                // The speed s whose stretch leaves a distance it can still
                // brake in: s^2 = 2 a (d - s h), so s = -a h + sqrt((a h)^2
                // + 2 a d). Never past the goal (s h <= d).
                let ah = ACCELERATION * h;
                let braking = -ah + (ah * ah + 2.0 * ACCELERATION * d).sqrt();
                to_goal.normalize_or_zero() * MAX_SPEED.min(braking)
            }
            None => Vec3::ZERO,
        };
        let change = (wanted - self.velocity).clamp_length_max(ACCELERATION * h);
        self.velocity + change
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field() -> (Vec2, Vec2) {
        (Vec2::splat(-5.0), Vec2::splat(5.0))
    }

    /// Rolled to a point 3 m away in frames of 1/30 s: it speeds up no
    /// faster than `ACCELERATION`, never beyond `MAX_SPEED`, arrives and
    /// stops on the point; the stretches join end to start (each starts
    /// where the last ended, at its time), and the turn it carries is the
    /// turn of rolling without slipping over the whole way.
    #[test]
    fn a_rolled_ball_speeds_up_slows_down_and_stops_on_its_goal() {
        let (low, high) = field();
        let mut ball = Ball::new(Vec3::new(-1.0, 0.0, 0.0), low, high, Terrain::default());
        let goal = ball.roll_to(Vec3::new(2.0, 0.0, 0.0));
        let h = 1.0 / 30.0;
        let mut t = 10.0f32;
        let mut last_end = ball.centre;
        let mut last_speed = 0.0f32;
        let mut travelled = 0.0f32;
        let mut arrived = None;
        for _ in 0..300 {
            let (c, a) = ball.stretch(t, t + h);
            let (from, v, _) = c.motion_at(t);
            assert!(
                from.distance(last_end) < 1e-5,
                "a stretch starts where the last ended"
            );
            let speed = v.length();
            assert!(speed <= MAX_SPEED + 1e-4, "{speed}");
            assert!(
                (speed - last_speed).abs() <= ACCELERATION * h + 1e-4,
                "{last_speed} -> {speed}"
            );
            let (to, _, _) = c.motion_at(t + h);
            assert!(to.distance(ball.centre) < 1e-5);
            travelled += to.distance(from);
            (last_end, last_speed, t) = (to, speed, t + h);
            if let Some(Arrived(at)) = a {
                arrived = Some((at, t));
                break;
            }
        }
        let (at, when) = arrived.expect("it arrives");
        assert!(
            travelled < 3.0 + 1e-3,
            "it went past its goal: {travelled} m for 3"
        );
        assert!(at.distance(goal) < ARRIVED, "{at} vs {goal}");
        // 3 m: 1 s speeding up to 2 m/s, 0.5 m at full speed, 1 s slowing:
        // 2.25 s at best; frames add a little.
        let took = when - 10.0;
        assert!((2.2..2.8).contains(&took), "took {took} s");
        // One straight way along +x: turned about up x (+x) = -z by the
        // distance over the radius.
        let expected = Quat::from_axis_angle(Vec3::NEG_Z, travelled / BALL_RADIUS);
        assert!(
            ball.turned.angle_between(expected) < 1e-3,
            "{} {expected} {travelled}",
            ball.turned
        );
        // At rest, a still collider.
        let (c, _) = ball.stretch(t, t + h);
        assert!(c.path.is_empty() && c.position == ball.centre);
    }

    #[test]
    fn the_ball_stays_within_its_rectangle() {
        let (low, high) = field();
        let mut ball = Ball::new(Vec3::new(9.0, 0.0, -9.0), low, high, Terrain::default());
        assert_eq!(
            ball.centre,
            Vec3::new(5.0 - BALL_RADIUS, BALL_RADIUS, -5.0 + BALL_RADIUS)
        );
        let goal = ball.roll_to(Vec3::new(-20.0, 0.0, 0.0));
        assert_eq!(goal.x, -5.0 + BALL_RADIUS);
        for i in 0..600 {
            let t = i as f32 / 60.0;
            ball.stretch(t, t + 1.0 / 60.0);
            assert!(
                ball.centre.x >= -5.0 + BALL_RADIUS - 1e-5,
                "{}",
                ball.centre
            );
        }
        assert!(ball.centre.distance(goal) < ARRIVED);
    }

    /// Over a hill it rests and rolls on the ground: every stretch ends
    /// with its centre its radius above the ground there, and it arrives
    /// on the far side.
    #[test]
    fn over_a_hill_the_ball_rolls_on_the_ground() {
        use crate::model::terrain::Hill;
        let (low, high) = field();
        let hill = Terrain {
            hills: vec![Hill {
                center: [0.0, 0.5],
                height: 1.0,
                half_width: 1.5,
            }],
            ..Terrain::default()
        };
        let mut ball = Ball::new(Vec3::new(-3.0, 0.0, 0.0), low, high, hill.clone());
        let on_ground = |c: Vec3| (c.y - hill.height(c.x, c.z) - BALL_RADIUS).abs() < 1e-5;
        assert!(on_ground(ball.centre), "{}", ball.centre);
        let goal = ball.roll_to(Vec3::new(3.0, 0.0, 0.0));
        assert!(on_ground(goal), "{goal}");
        let mut highest = f32::MIN;
        let mut arrived = false;
        for i in 0..600 {
            let t = i as f32 / 30.0;
            let (c, a) = ball.stretch(t, t + 1.0 / 30.0);
            let (from, _, _) = c.motion_at(t);
            assert!(
                on_ground(from) && on_ground(ball.centre),
                "{from} {}",
                ball.centre
            );
            highest = highest.max(ball.centre.y);
            if a.is_some() {
                arrived = true;
                break;
            }
        }
        assert!(arrived && ball.centre.distance(goal) < ARRIVED);
        // It went over the hill's shoulder (0.85 m high on its way).
        assert!(highest > 0.8, "{highest}");
    }
}
