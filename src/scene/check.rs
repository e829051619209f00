//! The checks a scene must pass, each naming the field by its path in the
//! scene file (`grass.meadow[0].count`) and the range it allows. The file
//! loader turns the path into a line and column.

use std::fmt::Display;
use std::ops::RangeInclusive;

use glam::Vec3;

use super::{Camera, Cover, Scene};
use crate::error::Error;
use crate::model::contact::{Collider, ColliderKind, MAX_COLLIDERS};
use crate::model::terrain::Terrain;

/// The most frames one run may write.
pub const MAX_FRAMES: u32 = 100_000;

/// The largest image side accepted before asking the device (lavapipe's
/// maxImageDimension2D; most GPUs allow as much).
pub const MAX_IMAGE_SIDE: u32 = 16384;
/// The most multigrid V-cycles a step may run (each costs about eight Jacobi iterations).
pub const MAX_V_CYCLES: u32 = 100;
/// The fastest a wind source or collider may travel its path (m/s): a
/// thousand metres a second crosses the largest wind grid in a few steps.
pub const MAX_PATH_SPEED: f32 = 1000.0;

/// How far the camera sees (m): the far plane of its projection. Grass
/// beyond it is not drawn.
pub const VIEW_DISTANCE: f32 = 200.0;

/// A scene value out of its range: where, and what is allowed.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldError {
    /// Dotted path from the file's root, with [index] for array entries.
    pub path: String,
    pub message: String,
}

impl FieldError {
    pub fn new(path: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            message: message.into(),
        }
    }

    /// The same error one level further down: `prefix.path`.
    pub fn at(self, prefix: &str) -> Self {
        let path = if self.path.is_empty() {
            prefix.to_string()
        } else if self.path.starts_with('[') {
            format!("{prefix}{}", self.path)
        } else {
            format!("{prefix}.{}", self.path)
        };
        Self { path, ..self }
    }
}

impl From<FieldError> for Error {
    fn from(e: FieldError) -> Self {
        Error::InvalidInput(format!("{}: {}", e.path, e.message))
    }
}

pub type Check = std::result::Result<(), FieldError>;

/// `value` must lie in `range`.
pub fn in_range<T: PartialOrd + Display>(name: &str, value: T, range: RangeInclusive<T>) -> Check {
    if range.contains(&value) {
        Ok(())
    } else {
        Err(FieldError::new(
            name,
            format!(
                "{value} is not allowed, use {}..={}",
                range.start(),
                range.end()
            ),
        ))
    }
}

/// A finite number above zero and at most `max`.
pub fn positive(name: &str, value: f32, max: f32) -> Check {
    if value.is_finite() && value > 0.0 && value <= max {
        Ok(())
    } else {
        Err(FieldError::new(
            name,
            format!("{value} is not allowed, use a number above 0 and at most {max}"),
        ))
    }
}

/// A number in `range` (NaN and the infinities are not), else an error
/// that says what to use `instead`.
pub fn within(name: &str, value: f32, range: RangeInclusive<f32>, instead: &str) -> Check {
    if range.contains(&value) {
        Ok(())
    } else {
        Err(FieldError::new(
            name,
            format!("{value} is not allowed, use {instead}"),
        ))
    }
}

pub fn finite(name: &str, values: &[f32]) -> Check {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(FieldError::new(
            name,
            format!("{values:?} is not allowed, every value must be a finite number"),
        ))
    }
}

/// A [min, max] range inside `allowed`, not reversed.
pub(super) fn range_within(name: &str, [lo, hi]: [f32; 2], allowed: RangeInclusive<f32>) -> Check {
    finite(name, &[lo, hi])?;
    if lo > hi {
        return Err(FieldError::new(
            name,
            format!("[{lo}, {hi}] is reversed, write [min, max]"),
        ));
    }
    if !(allowed.contains(&lo) && allowed.contains(&hi)) {
        return Err(FieldError::new(
            name,
            format!(
                "[{lo}, {hi}] is not allowed, keep both ends within {}..={}",
                allowed.start(),
                allowed.end()
            ),
        ));
    }
    Ok(())
}

pub fn scene(s: &Scene) -> Check {
    if s.name.trim().is_empty() {
        return Err(FieldError::new("name", "is empty, give the scene a name"));
    }
    s.render.check().map_err(|e| e.at("render"))?;
    s.camera.check().map_err(|e| e.at("camera"))?;
    s.light.check().map_err(|e| e.at("light"))?;
    s.lod.check().map_err(|e| e.at("lod"))?;
    s.cull.check().map_err(|e| e.at("cull"))?;
    s.ground.check().map_err(|e| e.at("ground"))?;
    s.grass.check().map_err(|e| e.at("grass"))?;
    camera_reaches_grass(s).map_err(|e| e.at("camera"))?;
    s.wind.check().map_err(|e| e.at("wind"))?;
    if s.grass.cover.is_some() {
        s.wind.check_moving_window().map_err(|e| e.at("wind"))?;
    }
    if s.colliders.len() > MAX_COLLIDERS {
        return Err(FieldError::new(
            "collider",
            format!(
                "{} colliders is not allowed, use at most {MAX_COLLIDERS}",
                s.colliders.len()
            ),
        ));
    }
    for (i, c) in s.colliders.iter().enumerate() {
        collider(c).map_err(|e| e.at(&format!("collider[{i}]")))?;
    }
    above_ground(s)
}

/// The camera (its position, its path's keys and the lines between them)
/// and every collider (where it stands, or anywhere along its path) over
/// the ground where they are: from under it the meadow would be seen from
/// below, floating in the sky, and a collider would press blades from
/// inside the hill. A hollow's floor may lie under y = 0. The file loader
/// runs it again once a height map is read.
pub fn above_ground(s: &Scene) -> Check {
    let terrain = s.ground.terrain();
    camera_above_ground(&s.camera, &terrain).map_err(|e| e.at("camera"))?;
    for (i, c) in s.colliders.iter().enumerate() {
        collider_above_ground(c, &terrain).map_err(|e| e.at(&format!("collider[{i}]")))?;
    }
    Ok(())
}

fn camera_above_ground(c: &Camera, terrain: &Terrain) -> Check {
    let under = |p: Vec3| {
        let ground = terrain.height(p.x, p.z);
        (p.y < ground).then_some(ground)
    };
    // With a path, the position is not where the camera is (`Camera::at`).
    let position = c
        .path
        .is_empty()
        .then(|| ("position".to_string(), c.position));
    let keys = position.into_iter().chain(
        c.path
            .iter()
            .enumerate()
            .map(|(k, key)| (format!("path[{k}].position"), key.position)),
    );
    for (field, p) in keys {
        let p = Vec3::from(p);
        let Some(ground) = under(p) else { continue };
        let message = if terrain.is_flat() {
            format!("is {} m under the ground (y < 0); raise it to y >= 0", -p.y)
        } else {
            format!(
                "is {:.2} m under the ground, whose surface at x {:.1}, z {:.1} is at y {ground:.2}; raise it to y >= {ground:.2} or move it off the rise",
                ground - p.y,
                p.x,
                p.z
            )
        };
        return Err(FieldError::new(field, message));
    }
    // Between keys the camera moves in a straight line (`Camera::at`):
    // every 0.25 m of it, at most 4096 points a stretch.
    for (k, pair) in c.path.windows(2).enumerate() {
        let (a, b) = (Vec3::from(pair[0].position), Vec3::from(pair[1].position));
        let n = ((a.distance(b) / 0.25).ceil() as usize).clamp(1, 4096);
        let deepest = (1..n)
            .map(|i| a.lerp(b, i as f32 / n as f32))
            .filter_map(|p| under(p).map(|ground| (ground - p.y, p, ground)))
            .max_by(|x, y| x.0.total_cmp(&y.0));
        if let Some((depth, p, ground)) = deepest {
            return Err(FieldError::new(
                "path",
                format!(
                    "passes {depth:.2} m under the ground between path[{k}] and path[{}] (deepest at x {:.1}, z {:.1}, where the ground is at y {ground:.2}); raise those keys or add one between them above the ground",
                    k + 1,
                    p.x,
                    p.z
                ),
            ));
        }
    }
    Ok(())
}

fn collider_above_ground(c: &Collider, terrain: &Terrain) -> Check {
    // Sampled on rings: a collider resting on a slope is clear within 1 mm.
    let tolerance = if terrain.is_flat() { 1e-4 } else { 1e-3 };
    let (depth, centre) = c.depth_in(terrain);
    if depth <= tolerance {
        return Ok(());
    }
    if c.path.is_empty() && c.position == Vec3::ZERO {
        return Err(FieldError::new(
            "position",
            "is missing (or the origin), which puts it under the ground; give position (it \
             stands there) or path (it moves along it)",
        ));
    }
    let field = if c.path.is_empty() {
        "position"
    } else {
        "path"
    };
    let message = if terrain.is_flat() {
        format!(
            "reaches {depth:.3} m below the ground, where the grass is rooted; raise it so its \
             lowest point is at y >= 0 (a sphere's centre at y >= its radius)"
        )
    } else {
        let lowest = match c.kind {
            ColliderKind::Sphere => "its centre",
            ColliderKind::Capsule => "its lowest point",
        };
        format!(
            "reaches {depth:.3} m into the ground near x {:.1}, z {:.1} (its surface must clear the ground's, a hill's side too); raise {lowest} there by at least {depth:.3} m",
            centre.x, centre.z
        )
    };
    Err(FieldError::new(field, message))
}

/// Every camera position (and key of its path) within the view's reach
/// of some grass: farther, the frame would hold no blade at all (a camera
/// 1e7 m away rendered sky and haze and exited 0).
fn camera_reaches_grass(s: &Scene) -> Check {
    match &s.grass.cover {
        // A cover grows around the camera wherever it goes.
        Some(c) if c.size.is_none() => return Ok(()),
        // A bounded one only where the camera comes within its view
        // distance of its rectangle (or the patches are in view).
        Some(c) if s.grass.bunch.is_empty() && s.grass.meadow.is_empty() => {
            return camera_reaches_cover(s, c)
        }
        _ => {}
    }
    let (lo, hi) = s.grass_reach_bounds();
    // The grass lies between the lowest ground under it and its tallest
    // blade over the highest.
    let step = ((hi[0] - lo[0]).max(hi[1] - lo[1]) / 64.0).max(0.1);
    let (low, high) = s.ground.terrain().range_over(lo, hi, step);
    let (low, high) = (low.min(0.0), high.max(0.0) + s.grass.shape.height[1]);
    for (field, p) in camera_keys(s) {
        let (dx, dy, dz) = (
            gap(p[0], lo[0], hi[0]),
            gap(p[1], low, high),
            gap(p[2], lo[1], hi[1]),
        );
        let distance = (dx * dx + dy * dy + dz * dz).sqrt();
        if distance > VIEW_DISTANCE {
            return Err(FieldError::new(
                field,
                format!(
                    "is {distance:.0} m from the nearest grass and the view reaches {VIEW_DISTANCE:.0} m; move it within {VIEW_DISTANCE:.0} m of the grass (from x {:.1}..{:.1}, z {:.1}..{:.1})",
                    lo[0], hi[0], lo[1], hi[1]
                ),
            ));
        }
    }
    Ok(())
}

/// The camera's position and its path's keys', each with its field.
fn camera_keys(s: &Scene) -> impl Iterator<Item = (String, [f32; 3])> + '_ {
    let c = &s.camera;
    std::iter::once(("position".to_string(), c.position)).chain(
        c.path
            .iter()
            .enumerate()
            .map(|(k, key)| (format!("path[{k}].position"), key.position)),
    )
}

/// How far `x` lies outside [a, b] (0 within).
fn gap(x: f32, a: f32, b: f32) -> f32 {
    (a - x).max(x - b).max(0.0)
}

/// Every camera position (and key of its path) within the bounded
/// cover's view distance of its rectangle: farther, no tile around the
/// camera holds a blade.
fn camera_reaches_cover(s: &Scene, c: &Cover) -> Check {
    let [x0, z0, x1, z1] = c.bounds();
    for (field, p) in camera_keys(s) {
        let (dx, dz) = (gap(p[0], x0, x1), gap(p[2], z0, z1));
        if dx.max(dz) > c.view_distance {
            return Err(FieldError::new(
                field,
                format!(
                    "is {:.0} m from the grass.cover's rectangle (x {x0}..{x1}, z {z0}..{z1}), beyond its view_distance of {} m, where no tile holds a blade; move it nearer, or widen the cover's size",
                    (dx * dx + dz * dz).sqrt(),
                    c.view_distance
                ),
            ));
        }
    }
    Ok(())
}

fn collider(c: &Collider) -> Check {
    positive("radius", c.radius, 100.0)?;
    match c.kind {
        ColliderKind::Sphere => {
            if c.height != 0.0 {
                return Err(FieldError::new(
                    "height",
                    "is for capsules; a sphere's size is its radius (drop height)",
                ));
            }
        }
        ColliderKind::Capsule => {
            finite("height", &[c.height])?;
            if !(c.height >= 2.0 * c.radius && c.height <= 100.0) {
                return Err(FieldError::new(
                    "height",
                    format!(
                        "{} is not allowed, use 2 x radius ({}) ..= 100 m: the whole height, caps included",
                        c.height,
                        2.0 * c.radius
                    ),
                ));
            }
            if c.roll {
                return Err(FieldError::new(
                    "roll",
                    "is for spheres; a capsule stands upright",
                ));
            }
        }
    }
    finite("position", &c.position.to_array())?;
    if !c.path.is_empty() && c.position != Vec3::ZERO {
        return Err(FieldError::new(
            "position",
            "and path both place it; give position (it stands) or path (it moves), not both",
        ));
    }
    path(&c.path, c.path_speed)?;
    if !(c.start.is_finite() && (0.0..=1e6).contains(&c.start)) {
        return Err(FieldError::new(
            "start",
            format!("{} is not allowed, use 0 ..= 1e6 s", c.start),
        ));
    }
    Ok(())
}

/// Waypoints and the speed along them, as a wind source or a collider has.
pub(super) fn path(points: &[glam::Vec3], speed: f32) -> Check {
    for (i, p) in points.iter().enumerate() {
        finite(&format!("path[{i}]"), &p.to_array())?;
    }
    if points.len() > crate::model::wind::MAX_PATH_POINTS {
        return Err(FieldError::new(
            "path",
            format!(
                "{} points is not allowed, use at most {}",
                points.len(),
                crate::model::wind::MAX_PATH_POINTS
            ),
        ));
    }
    if !(speed.is_finite() && (0.0..=MAX_PATH_SPEED).contains(&speed)) {
        return Err(FieldError::new(
            "path_speed",
            format!("{speed} is not allowed, use 0 ..= {MAX_PATH_SPEED} m/s"),
        ));
    }
    if speed > 0.0 && points.len() < 2 {
        return Err(FieldError::new(
            "path_speed",
            "moves it along its path, which needs at least 2 points (give `path`, or drop path_speed)",
        ));
    }
    Ok(())
}
