//! The checks a scene must pass, each naming the field by its path in the
//! scene file (`grass.meadow[0].count`) and the range it allows. The file
//! loader turns the path into a line and column.

use std::fmt::Display;
use std::ops::RangeInclusive;

use glam::Vec3;

use super::{
    Camera, Cover, Cull, Grass, GrassDynamics, Light, Lod, RenderSettings, Scene, MAX_BLADES,
};
use crate::error::Error;
use crate::model::contact::{Collider, ColliderKind, MAX_COLLIDERS};
use crate::model::terrain::Terrain;
use crate::model::wind::{Obstacle, WindSource, MAX_CELLS};
use crate::model::BladePhysics;

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
fn range_within(name: &str, [lo, hi]: [f32; 2], allowed: RangeInclusive<f32>) -> Check {
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
    render(&s.render).map_err(|e| e.at("render"))?;
    camera(&s.camera).map_err(|e| e.at("camera"))?;
    light(&s.light).map_err(|e| e.at("light"))?;
    lod(&s.lod).map_err(|e| e.at("lod"))?;
    cull(&s.cull).map_err(|e| e.at("cull"))?;
    s.ground.check().map_err(|e| e.at("ground"))?;
    grass(&s.grass).map_err(|e| e.at("grass"))?;
    camera_reaches_grass(s).map_err(|e| e.at("camera"))?;
    wind(&s.wind).map_err(|e| e.at("wind"))?;
    if s.grass.cover.is_some() {
        moving_wind_window(&s.wind).map_err(|e| e.at("wind"))?;
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

/// With `[grass.cover]` the wind grid is a window that follows the camera
/// in whole cells, its air shifted with it (src/model/wind/window.rs):
/// what is fixed to the grid's sides or cells would move with it.
fn moving_wind_window(w: &super::WindConfig) -> Check {
    if w.inflow.is_some_and(|i| i.gust.amplitude != 0.0) {
        return Err(FieldError::new(
            "inflow.gust",
            "enters at the wind window's upwind side, which follows the camera with [grass.cover]; remove the gust and use wind.turbulence, which is alive everywhere",
        ));
    }
    if !w.obstacles.is_empty() {
        return Err(FieldError::new(
            "obstacle",
            format!(
                "{} obstacles with [grass.cover]: its wind window follows the camera and holds no fixed solid cells yet; remove the [[wind.obstacle]] or the cover",
                w.obstacles.len()
            ),
        ));
    }
    Ok(())
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

pub fn render(r: &RenderSettings) -> Check {
    in_range("width", r.width, 1..=MAX_IMAGE_SIDE)?;
    in_range("height", r.height, 1..=MAX_IMAGE_SIDE)?;
    if !r.msaa.is_power_of_two() || r.msaa > 64 {
        return Err(FieldError::new(
            "msaa",
            format!(
                "{} is not a sample count, use 1, 2, 4, 8, 16, 32 or 64",
                r.msaa
            ),
        ));
    }
    in_range("frames", r.frames, 1..=MAX_FRAMES)?;
    positive("fps", r.fps, 1000.0)?;
    within("start", r.start, 0.0..=86_400.0, "0..=86400 seconds")?;
    Ok(())
}

pub fn camera(c: &Camera) -> Check {
    let points = std::iter::once((c.position, c.target))
        .chain(c.path.iter().map(|k| (k.position, k.target)));
    for (i, (position, target)) in points.enumerate() {
        let at = |name: &str| {
            if i == 0 {
                name.to_string()
            } else {
                format!("path[{}].{name}", i - 1)
            }
        };
        finite(&at("position"), &position)?;
        finite(&at("target"), &target)?;
        if position == target {
            return Err(FieldError::new(
                at("target"),
                "equals the position; the camera must look somewhere",
            ));
        }
    }
    if !(c.fov_y.is_finite() && c.fov_y > 1.0 && c.fov_y < 170.0) {
        return Err(FieldError::new(
            "fov_y",
            format!("{} is not allowed, use 1 < fov_y < 170 degrees", c.fov_y),
        ));
    }
    for (i, k) in c.path.iter().enumerate() {
        finite(&format!("path[{i}].time"), &[k.time])?;
    }
    for (i, pair) in c.path.windows(2).enumerate() {
        if pair[1].time <= pair[0].time {
            return Err(FieldError::new(
                format!("path[{}].time", i + 1),
                format!(
                    "{} is not after the previous key's {}; keyframe times must increase",
                    pair[1].time, pair[0].time
                ),
            ));
        }
    }
    Ok(())
}

pub fn light(l: &Light) -> Check {
    finite("direction", &l.direction)?;
    if Vec3::from(l.direction).length() < 1e-6 {
        return Err(FieldError::new(
            "direction",
            "is zero, give the direction toward the light",
        ));
    }
    if l.direction[1] < 0.0 {
        return Err(FieldError::new(
            "direction",
            format!(
                "{:?} points below the horizon (y < 0): the light would shine up through the ground; give the direction toward the sun, y >= 0",
                l.direction
            ),
        ));
    }
    finite("color", &l.color)?;
    if l.color.iter().any(|&c| !(0.0..=100.0).contains(&c)) {
        return Err(FieldError::new(
            "color",
            format!("{:?} is not allowed, use values in 0..=100", l.color),
        ));
    }
    in_range("shadow_map", l.shadow_map, 0..=MAX_IMAGE_SIDE)?;
    if !(0.0..=1.0).contains(&l.ambient) {
        return Err(FieldError::new(
            "ambient",
            format!("{} is not allowed, use 0..=1", l.ambient),
        ));
    }
    Ok(())
}

pub fn lod(l: &Lod) -> Check {
    positive("close_distance", l.close_distance, 1e6)?;
    positive("far_distance", l.far_distance, 1e6)?;
    if l.far_distance < l.close_distance {
        return Err(FieldError::new(
            "far_distance",
            format!(
                "{} is nearer than close_distance {}; use close <= far",
                l.far_distance, l.close_distance
            ),
        ));
    }
    for (i, &level) in l.levels.iter().enumerate() {
        in_range(&format!("levels[{i}]"), level, 1..=64)?;
    }
    for (i, &level) in l.shadow_levels.iter().enumerate() {
        in_range(&format!("shadow_levels[{i}]"), level, 1..=64)?;
    }
    Ok(())
}

pub fn cull(c: &Cull) -> Check {
    within(
        "thin_from",
        c.thin_from,
        0.0..=1e6,
        "0 (no thinning) or a distance up to 1e6 m",
    )?;
    within(
        "thin_least",
        c.thin_least,
        0.01..=1.0,
        "a share in 0.01..=1 (1 keeps every blade)",
    )?;
    positive("thin_band", c.thin_band, 1.0)?;
    within(
        "edge_on",
        c.edge_on,
        0.5..=1.0,
        "a cosine in 0.5..=1 (1 keeps blades seen edge-on)",
    )?;
    Ok(())
}

pub fn grass(g: &Grass) -> Check {
    if g.bunch.is_empty() && g.meadow.is_empty() && g.cover.is_none() {
        return Err(FieldError::new(
            "",
            "the scene has no grass; add a [[grass.bunch]], a [[grass.meadow]] or a [grass.cover]",
        ));
    }
    let shape = &g.shape;
    let weights = [shape.upright, shape.curved, shape.drooping];
    for (name, w) in ["upright", "curved", "drooping"].into_iter().zip(weights) {
        if !(w.is_finite() && w >= 0.0) {
            return Err(FieldError::new(
                format!("shape.{name}"),
                format!("{w} is not allowed, use a weight >= 0"),
            ));
        }
    }
    if weights.iter().sum::<f32>() <= 0.0 {
        return Err(FieldError::new(
            "shape",
            "the weights upright, curved and drooping are all zero; make one positive",
        ));
    }
    range_within("shape.height", shape.height, 0.01..=10.0)?;
    range_within("shape.width", shape.width, 0.0005..=1.0)?;
    dynamics(&g.dynamics).map_err(|e| e.at("dynamics"))?;
    look(&g.look).map_err(|e| e.at("look"))?;

    for (i, b) in g.bunch.iter().enumerate() {
        let at = format!("bunch[{i}]");
        finite(&format!("{at}.center"), &b.center)?;
        positive(&format!("{at}.radius"), b.radius, 10_000.0)?;
        in_range(&format!("{at}.count"), b.count, 1..=MAX_BLADES)?;
    }
    for (i, m) in g.meadow.iter().enumerate() {
        let at = format!("meadow[{i}]");
        finite(&format!("{at}.center"), &m.center)?;
        positive(&format!("{at}.size[0]"), m.size[0], 10_000.0)?;
        positive(&format!("{at}.size[1]"), m.size[1], 10_000.0)?;
        match (m.count, m.density) {
            (Some(n), None) => in_range(&format!("{at}.count"), n, 1..=MAX_BLADES)?,
            (None, Some(d)) => {
                positive(&format!("{at}.density"), d, 1e6)?;
                in_range(&format!("{at}.density"), m.blades(), 1..=MAX_BLADES).map_err(
                    |_| {
                        FieldError::new(
                            format!("{at}.density"),
                            format!(
                                "{d} per square metre gives {} blades, use a density giving 1..={MAX_BLADES}",
                                m.blades()
                            ),
                        )
                    },
                )?
            }
            (Some(_), Some(_)) => {
                return Err(FieldError::new(
                    at,
                    "has both count and density; give one of them",
                ))
            }
            (None, None) => {
                return Err(FieldError::new(
                    at,
                    "has neither count nor density; give one of them",
                ))
            }
        }
        if m.mask
            .as_ref()
            .is_some_and(|name| name.written.trim().is_empty())
        {
            return Err(FieldError::new(
                format!("{at}.mask"),
                "is empty; name a grey PNG relative to the scene file",
            ));
        }
    }
    let total = g.blade_count();
    if total > MAX_BLADES {
        return Err(FieldError::new(
            "",
            format!("{total} blades in all is not allowed, use at most {MAX_BLADES}"),
        ));
    }
    if let Some(c) = &g.cover {
        cover(c, MAX_BLADES - total).map_err(|e| e.at("cover"))?;
    }
    Ok(())
}

/// `[grass.look]`'s values, each in its range.
fn look(l: &crate::scene::Look) -> Check {
    let unit = "a number from 0 to 1";
    within("hue", l.hue, 0.0..=1.0, unit)?;
    within("dryness", l.dryness, 0.0..=1.0, unit)?;
    within("tip", l.tip, 0.0..=1.0, unit)?;
    within(
        "clump_size",
        l.clump_size,
        0.0..=10.0,
        "metres from 0 (no clumps) to 10",
    )?;
    within("clump_variation", l.clump_variation, 0.0..=1.0, unit)?;
    within(
        "sheen",
        l.sheen,
        0.0..=4.0,
        "a number from 0 (none) to 4 (1: a leaf's)",
    )?;
    within(
        "translucency",
        l.translucency,
        0.0..=4.0,
        "a number from 0 (none) to 4 (1: a leaf's)",
    )
}

/// The widest bounded cover (m) and the farthest its centre lies from
/// the origin: 100 km, where f32 roots still fall within 8 mm of where
/// the draws put them.
pub const MAX_COVER_SIZE: f32 = 100_000.0;

/// The cover's values, and the blades it makes around the camera within
/// the `room` the patches leave of `MAX_BLADES`.
pub fn cover(c: &Cover, room: usize) -> Check {
    positive("density", c.density(), 10_000.0)?;
    positive("view_distance", c.view_distance, VIEW_DISTANCE)?;
    within(
        "simulate_radius",
        c.simulate_radius(),
        0.0..=c.view_distance,
        &format!(
            "a distance in 0..={} m (the view distance)",
            c.view_distance
        ),
    )?;
    match (c.size, c.center) {
        (Some([w, d]), center) => {
            positive("size[0]", w, MAX_COVER_SIZE)?;
            positive("size[1]", d, MAX_COVER_SIZE)?;
            if let Some(center) = center {
                finite("center", &center)?;
                within(
                    "center",
                    center[0].abs().max(center[1].abs()),
                    0.0..=MAX_COVER_SIZE,
                    &format!("a centre within {MAX_COVER_SIZE} m of the origin"),
                )?;
            }
        }
        (None, Some(_)) => {
            return Err(FieldError::new(
                "center",
                "is the centre of the cover's rectangle, which has no size; add size = [w, d] (m) or remove center",
            ))
        }
        (None, None) => {}
    }
    let blades = super::cover::most_blades(c);
    if blades > room as u64 {
        let side = 2 * super::cover::tiles_reached(c.view_distance) + 1;
        return Err(FieldError::new(
            "view_distance",
            format!(
                "{} m at {} blades a square metre makes {side} x {side} tiles of {} blades, {blades} blades ({:.1} GB of control points), over the {room} allowed; lower view_distance or density",
                c.view_distance,
                c.density(),
                super::cover::per_tile(c.density()),
                blades as f64 * 128.0 / 1e9
            ),
        ));
    }
    Ok(())
}

pub fn dynamics(d: &GrassDynamics) -> Check {
    for (name, range) in d.ranges() {
        range_within(name, range, f32::MIN..=f32::MAX)?;
    }
    for corner in d.corners() {
        blade_physics(&corner)?;
    }
    Ok(())
}

/// One blade's parameters, named as in `[grass.dynamics]`.
fn blade_physics(p: &BladePhysics) -> Check {
    match p.first_invalid() {
        Some((name, value, allowed)) => Err(FieldError::new(
            name,
            format!("a range reaching {value} is not allowed, use {allowed}"),
        )),
        None => Ok(()),
    }
}

pub fn wind(w: &super::WindConfig) -> Check {
    for (a, &n) in w.cells.iter().enumerate() {
        in_range(&format!("cells[{a}]"), n, 1..=4096)?;
    }
    let cells: u64 = w.cells.iter().map(|&n| n as u64).product();
    if cells > MAX_CELLS {
        return Err(FieldError::new(
            "cells",
            format!("{cells} cells is not allowed, use at most {MAX_CELLS}"),
        ));
    }
    positive("height", w.height, 1000.0)?;
    within("margin", w.margin, 0.0..=1000.0, "0..=1000 m")?;
    positive("window[0]", w.window[0], 10_000.0)?;
    positive("window[1]", w.window[1], 10_000.0)?;
    in_range("jacobi_iterations", w.jacobi_iterations, 0..=10_000)?;
    in_range("v_cycles", w.v_cycles, 1..=MAX_V_CYCLES)?;
    within("canopy_drag", w.canopy_drag, 0.0..=10.0, "0..=10")?;
    positive("dt", w.dt, 0.1)?;
    for (i, s) in w.sources.iter().enumerate() {
        source(s).map_err(|e| e.at(&format!("source[{i}]")))?;
    }
    if let Some(inflow) = &w.inflow {
        finite("inflow.speed", &[inflow.speed])?;
        within(
            "inflow.heading",
            inflow.heading,
            -360.0..=360.0,
            "-360..=360 degrees (0 blows towards +x, 90 towards +z)",
        )?;
        if inflow.speed.abs() > 100.0 {
            return Err(FieldError::new(
                "inflow.speed",
                format!("{} is not allowed, use -100..=100 m/s", inflow.speed),
            ));
        }
        gust(&inflow.gust).map_err(|e| e.at("inflow.gust"))?;
    }
    for (i, o) in w.obstacles.iter().enumerate() {
        obstacle(o).map_err(|e| e.at(&format!("obstacle[{i}]")))?;
    }
    if let Some(t) = &w.turbulence {
        turbulence(t, w.inflow.is_some()).map_err(|e| e.at("turbulence"))?;
    }
    Ok(())
}

/// What can be checked without the grid (the length scale against the
/// cells: `Scene::wind_grid`).
fn turbulence(t: &crate::model::wind::Turbulence, inflow: bool) -> Check {
    positive("intensity", t.intensity, 2.0)?;
    positive("length_scale", t.length_scale, 100_000.0)?;
    if let Some(finest) = t.finest_wavelength {
        positive("finest_wavelength", finest, 100_000.0)?;
    }
    match t.speed {
        Some(speed) => positive("speed", speed, 100.0),
        None if inflow => Ok(()),
        None => Err(FieldError::new(
            "speed",
            "missing: without an inflow it is needed, as the intensity is sigma_u over this speed; give it in m/s (above 0 and at most 100)",
        )),
    }
}

fn gust(g: &crate::model::wind::Gust) -> Check {
    within("amplitude", g.amplitude, 0.0..=10.0, "0..=10")?;
    within("frequency", g.frequency, 0.0..=100.0, "0..=100 Hz")?;
    Ok(())
}

fn source(s: &WindSource) -> Check {
    finite("position", &s.position.to_array())?;
    finite("direction", &s.direction.to_array())?;
    if s.direction.length() < 1e-6 {
        return Err(FieldError::new(
            "direction",
            "is zero, give the direction the source pushes the air",
        ));
    }
    finite("strength", &[s.strength])?;
    if s.strength.abs() > 1000.0 {
        return Err(FieldError::new(
            "strength",
            format!("{} is not allowed, use -1000..=1000 m/s^2", s.strength),
        ));
    }
    positive("radius", s.radius, 10_000.0)?;
    finite("rotation_speed", &[s.rotation_speed])?;
    path(&s.path, s.path_speed)?;
    gust(&s.gust).map_err(|e| e.at("gust"))?;
    if let Some(off) = s.off_after {
        if !(off.is_finite() && off >= 0.0) {
            return Err(FieldError::new(
                "off_after",
                format!("{off} is not allowed, use a time of 0 s or more"),
            ));
        }
    }
    Ok(())
}

fn obstacle(o: &Obstacle) -> Check {
    match *o {
        Obstacle::Box { min, max } => {
            finite("min", &min.to_array())?;
            finite("max", &max.to_array())?;
            if min.cmpge(max).any() {
                return Err(FieldError::new(
                    "max",
                    format!("{max} is not above min {min} on every axis"),
                ));
            }
        }
        Obstacle::Sphere { center, radius } => {
            finite("center", &center.to_array())?;
            positive("radius", radius, 10_000.0)?;
        }
        Obstacle::Cylinder {
            base,
            radius,
            height,
        } => {
            finite("base", &base.to_array())?;
            positive("radius", radius, 10_000.0)?;
            positive("height", height, 10_000.0)?;
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
fn path(points: &[glam::Vec3], speed: f32) -> Check {
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
