//! What drives the wind: the inflow and its gusts, the sources, the
//! obstacles it flows round.

use glam::Vec3;

use super::{along_path, WindGrid};
use crate::error::{Error, Result};

/// Gusts: the signal
/// g(t) = 0.5 sin(2 pi f t + p0) + 0.3 sin(2 pi 2.17 f t + p1) + 0.2 sin(2 pi 4.73 f t + p2),
/// the phases p drawn from the seed. A source's strength is
/// s0 * max(0, 1 + a g(t)); an inflow's gusts are spatial and travel
/// (`Inflow::velocity_at`). a = 0: no gusts. In a scene file every field
/// is optional on its own (default 0).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Gust {
    pub amplitude: f32,
    /// Base frequency, Hz.
    pub frequency: f32,
    pub seed: u32,
}

impl Gust {
    pub const HARMONICS: [(f32, f32); 3] = [(1.0, 0.5), (2.17, 0.3), (4.73, 0.2)];

    /// The three phases, from the seed (a small integer hash, same on GPU upload).
    pub fn phases(&self) -> [f32; 3] {
        std::array::from_fn(|n| {
            let mut x = self
                .seed
                .wrapping_mul(0x9E37_79B9)
                .wrapping_add((n as u32).wrapping_mul(0x85EB_CA6B));
            x ^= x >> 16;
            x = x.wrapping_mul(0x7FEB_352D);
            x ^= x >> 15;
            (x as f32 / u32::MAX as f32) * std::f32::consts::TAU
        })
    }

    /// g at time t, each harmonic delayed by its own `delay` (s).
    fn signal(&self, t: f32, delay: [f32; 3]) -> f32 {
        let p = self.phases();
        Self::HARMONICS
            .iter()
            .zip(p)
            .zip(delay)
            .map(|((&(mult, weight), phase), delay)| {
                weight * (std::f32::consts::TAU * self.frequency * mult * (t - delay) + phase).sin()
            })
            .sum()
    }

    /// A source's strength factor at time t: max(0, 1 + a g(t)).
    pub fn factor(&self, t: f32) -> f32 {
        if self.amplitude == 0.0 {
            return 1.0;
        }
        (1.0 + self.amplitude * self.signal(t, [0.0; 3])).max(0.0)
    }
}

/// How far each harmonic's gust fronts lean across the inflow side: a
/// front reaches z later by `INFLOW_GUST_LEAN * z / |speed|` (harmonics 1
/// and 3) or earlier (harmonic 2), so fronts arrive oblique (about 27
/// degrees) and crossing, not as one wall along the whole side.
pub const INFLOW_GUST_LEAN: f32 = 0.5;
const INFLOW_GUST_LEAN_SIGN: [f32; 3] = [1.0, -1.0, 1.0];

impl Inflow {
    /// The inflow's velocity component `axis` (0: x, 2: z) at a point `x`
    /// of an entry side of `grid`, at time t (docs/physics.md, travelling
    /// gusts):
    ///
    /// u = U d (1 + a g(t - delay) cos(pi y / height)),
    ///
    /// d the heading's unit vector, y the height above the grid's floor
    /// and the delay the time a front takes to arrive: (x - x0) . d / |U|
    /// from the most upwind corner x0, plus the lean of the fronts across
    /// the wind, lean (x . d_perp) / |U| with d_perp = (-d_z, d_x)
    /// (heading 0: lean z / |U|).
    ///
    /// A gust is faster air near the ground and slower air aloft: the
    /// cosine has zero mean over the height, so the flux through the side
    /// stays U times its area at every instant and the projection cannot
    /// pass the gust through the whole field at once; advection carries it
    /// downwind at the wind's speed (the lowest vertical mode of the layer
    /// of air between the ground and the free-slip top travels unchanged).
    pub fn velocity_at(&self, axis: usize, grid: &WindGrid, x: Vec3, t: f32) -> f32 {
        let [c, s] = self.heading_vector();
        let component = if axis == 0 { c } else { s };
        if self.gust.amplitude == 0.0 {
            return self.speed * component;
        }
        let speed = self.speed.abs().max(1e-3);
        let lean = INFLOW_GUST_LEAN * (-s * x.x + c * x.z) / speed;
        // The most upwind corner of the grid, along the velocity.
        let size = grid.size();
        let corner = |d: f32, lo: f32, extent: f32| {
            if d * self.speed < 0.0 {
                lo + extent
            } else {
                lo
            }
        };
        let x0 = corner(c, grid.origin.x, size.x);
        let z0 = corner(s, grid.origin.z, size.z);
        let sign = if self.speed >= 0.0 { 1.0 } else { -1.0 };
        let arrival = sign * ((x.x - x0) * c + (x.z - z0) * s) / speed;
        let delay = INFLOW_GUST_LEAN_SIGN.map(|l| l * lean + arrival);
        let height = size.y;
        let profile = (std::f32::consts::PI * (x.y - grid.origin.y) / height).cos();
        self.speed * (1.0 + self.gust.amplitude * self.gust.signal(t, delay) * profile) * component
    }
}

impl Inflow {
    /// The inflow's component `axis` that air traced back to `back`
    /// carries in from outside, at time t: for a horizontal component
    /// whose trace left the grid through an entry side across the other
    /// horizontal axis (the inflow's tangential part along that side,
    /// which no face of the side holds), the inflow's velocity at the
    /// side; None otherwise, for a component the inflow has none of
    /// (heading 0: z), so a wind from the left is unchanged bit for bit,
    /// and for an inflow stilled to 0 m/s.
    pub fn entering(&self, axis: usize, grid: &WindGrid, back: Vec3, t: f32) -> Option<f32> {
        let [c, s] = self.heading_vector();
        if self.speed == 0.0 || axis == 1 || (if axis == 0 { c } else { s }) == 0.0 {
            return None;
        }
        let across = 2 - axis;
        let (lo, hi) = (
            grid.origin[across],
            grid.origin[across] + grid.size()[across],
        );
        let outside = match (self.side(across, 0), self.side(across, 1)) {
            (Side::Entry, _) => back[across] < lo,
            (_, Side::Entry) => back[across] > hi,
            _ => false,
        };
        outside.then(|| {
            let at = back.clamp(grid.origin, grid.origin + grid.size());
            self.velocity_at(axis, grid, at, t)
        })
    }
}

/// A wind source (docs/method.md section 3): a ball of force.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindSource {
    pub position: Vec3,
    /// Direction of the force at t = 0 (normalised on use).
    pub direction: Vec3,
    /// Force per unit mass at the centre (m/s^2).
    pub strength: f32,
    /// Radius of influence (m); the force falls off smoothly to zero there.
    pub radius: f32,
    /// The direction turns about the vertical at this rate (rad/s): paper Fig. 11.
    #[serde(default)]
    pub rotation_speed: f32,
    /// Waypoints of a closed path the source moves along (empty: it stays put).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub path: Vec<Vec3>,
    /// Speed along the path (m/s).
    #[serde(default)]
    pub path_speed: f32,
    #[serde(default)]
    pub gust: Gust,
    /// Sources can be switched off at this time (s); None: never.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub off_after: Option<f32>,
}

impl WindSource {
    pub fn fixed(position: Vec3, direction: Vec3, strength: f32, radius: f32) -> Self {
        Self {
            position,
            direction,
            strength,
            radius,
            rotation_speed: 0.0,
            path: Vec::new(),
            path_speed: 0.0,
            gust: Gust::default(),
            off_after: None,
        }
    }

    /// Position, unit direction and strength at time t.
    pub fn at(&self, t: f32) -> (Vec3, Vec3, f32) {
        let d = self.direction.try_normalize().unwrap_or(Vec3::X);
        let dir = turned_about_y(d, self.rotation_speed * t);
        let strength = match self.off_after {
            Some(off) if t >= off => 0.0,
            _ => self.strength * self.gust.factor(t),
        };
        (self.position_at(t), dir, strength)
    }

    fn position_at(&self, t: f32) -> Vec3 {
        along_path(&self.path, self.path_speed, true, t, self.position).0
    }

    /// Refuses what cannot be simulated; warns where the source lies
    /// outside `grid`.
    pub fn validate(&self, grid: &WindGrid) -> Result<Vec<String>> {
        let finite = self.position.is_finite()
            && self.direction.is_finite()
            && self.strength.is_finite()
            && self.radius.is_finite()
            && self.rotation_speed.is_finite()
            && self.path_speed.is_finite()
            && self.path.iter().all(|p| p.is_finite())
            && self.gust.amplitude.is_finite()
            && self.gust.frequency.is_finite();
        if !finite {
            return Err(Error::InvalidInput(
                "wind source: every value must be a finite number (found NaN or infinity)".into(),
            ));
        }
        if self.radius <= 0.0 {
            return Err(Error::InvalidInput(format!(
                "wind source radius {} is not allowed, use > 0",
                self.radius
            )));
        }
        let mut warnings = Vec::new();
        let lo = grid.origin;
        let hi = grid.origin + grid.size();
        let p = self.position;
        if p.cmplt(lo).any() || p.cmpgt(hi).any() {
            warnings.push(format!(
                "wind source at {} lies outside the wind domain {lo}..{hi}; only its reach inside counts",
                self.position
            ));
        }
        Ok(warnings)
    }
}

/// `v` turned by `angle` radians about +y (anticlockwise seen from above):
/// a rotating source's direction (paper Fig. 11), the viewer's heading.
pub fn turned_about_y(v: Vec3, angle: f32) -> Vec3 {
    let (s, c) = angle.sin_cos();
    Vec3::new(c * v.x + s * v.z, v.y, -s * v.x + c * v.z)
}

/// Smooth fall-off of a source's force with distance: (1 - (d/r)^2)^2 inside r.
pub fn falloff(distance: f32, radius: f32) -> f32 {
    let q = 1.0 - (distance / radius) * (distance / radius);
    if q > 0.0 {
        q * q
    } else {
        0.0
    }
}

/// Wind entering through one side of the domain (paper Fig. 10: from the left).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Inflow {
    /// Speed of the incoming air (m/s); negative blows against `heading`.
    pub speed: f32,
    /// Where it blows towards, degrees: 0 along +x (paper Fig. 10: from
    /// the left), 90 along +z. The sides it enters by and leaves by
    /// follow from it (`Inflow::side`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub heading: f32,
    #[serde(default)]
    pub gust: Gust,
}

fn is_zero(v: &f32) -> bool {
    *v == 0.0
}

/// What a side of the domain is to an inflow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The wind enters: its faces hold the inflow's velocity across them.
    Entry,
    /// The wind leaves: open, zero pressure outside.
    Exit,
    /// Along the wind: free-slip, as a wind tunnel's walls.
    Along,
}

impl Inflow {
    /// The unit vector (x, z) the heading points along; exactly (1, 0)
    /// at heading 0, so that today's wind from the left is unchanged bit
    /// for bit (glsl/wind/wind_kernel.glsl does the same).
    pub fn heading_vector(&self) -> [f32; 2] {
        if self.heading == 0.0 {
            return [1.0, 0.0];
        }
        let (s, c) = self.heading.to_radians().sin_cos();
        // A component under 1e-6 is the rounding of a heading along an
        // axis (cos 90 degrees is -4e-8 in f32): zero.
        let snap = |v: f32| if v.abs() < 1e-6 { 0.0 } else { v };
        [snap(c), snap(s)]
    }

    /// Its mean velocity (m/s): speed along the heading, none upwards.
    pub fn mean_velocity(&self) -> Vec3 {
        let [c, s] = self.heading_vector();
        Vec3::new(self.speed * c, 0.0, self.speed * s)
    }

    /// Whether the inflow blows across both horizontal axes.
    pub fn is_oblique(&self) -> bool {
        let [c, s] = self.heading_vector();
        c != 0.0 && s != 0.0
    }

    /// Side `end` (0: least, 1: greatest) across horizontal axis `axis`
    /// (0: x, 2: z). Only the heading and the speed's sign decide, so a
    /// speed set to zero keeps the sides; a side the heading has no
    /// component across lies along the wind.
    pub fn side(&self, axis: usize, end: u32) -> Side {
        let [c, s] = self.heading_vector();
        let sign = if self.speed >= 0.0 { 1.0 } else { -1.0 };
        let component = sign * if axis == 0 { c } else { s };
        let inward = if end == 0 { component } else { -component };
        if component == 0.0 {
            Side::Along
        } else if inward > 0.0 {
            Side::Entry
        } else {
            Side::Exit
        }
    }
}

/// An obstacle in world space (paper Fig. 13): an axis-aligned box, a
/// sphere, or an upright cylinder (a tree trunk, a post) standing on `base`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase", tag = "kind", deny_unknown_fields)]
pub enum Obstacle {
    Box {
        min: Vec3,
        max: Vec3,
    },
    Sphere {
        center: Vec3,
        radius: f32,
    },
    Cylinder {
        base: Vec3,
        radius: f32,
        height: f32,
    },
}

impl Obstacle {
    pub fn contains(&self, p: Vec3) -> bool {
        match *self {
            Obstacle::Box { min, max } => p.cmpge(min).all() && p.cmple(max).all(),
            Obstacle::Sphere { center, radius } => p.distance_squared(center) <= radius * radius,
            Obstacle::Cylinder {
                base,
                radius,
                height,
            } => {
                let d = p - base;
                (0.0..=height).contains(&d.y) && d.x * d.x + d.z * d.z <= radius * radius
            }
        }
    }
}
