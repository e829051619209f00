//! The viewer's hold on the wind: the arrow keys make the inflow stronger
//! or weaker and turn a heading; a click drops a gust on the ground, a
//! short-lived wind source blowing along the heading. What they change
//! goes to the GPU solver through `FrameRecorder::set_wind_drive` and
//! drives it from the next step on.
//!
//! The heading turns the inflow itself (the sides it enters and leaves by
//! follow it: `WindPass::set_drive` reclassifies the faces when they
//! change), the scene's own sources and the gusts.

use glam::{Vec3, Vec4};

use crate::model::terrain::Terrain;
use crate::model::wind::{turned_about_y, Inflow, WindSource};
use crate::render::frame_uniforms::view_projection;
use crate::scene::Scene;

/// Metres a second the inflow changes by per arrow press.
pub const SPEED_STEP: f32 = 0.5;
/// The strongest inflow the keys set (m/s).
pub const MAX_INFLOW: f32 = 15.0;
/// What a press scales the sources' strength by, where there is no inflow.
pub const STRENGTH_STEP: f32 = 1.25;
/// Degrees the heading turns per arrow press.
pub const TURN_STEP_DEG: f32 = 15.0;
/// A dropped gust: its force at the centre (m/s^2), reach (m), height of
/// its centre above the ground (m) and how long it blows (s).
pub const GUST_STRENGTH: f32 = 30.0;
pub const GUST_RADIUS: f32 = 2.0;
pub const GUST_HEIGHT: f32 = 0.5;
pub const GUST_SECONDS: f32 = 1.5;
/// Gusts blowing at once; a new one past this replaces the oldest.
pub const MAX_GUSTS: usize = 16;

#[derive(Clone, Debug)]
pub struct WindControls {
    /// The scene's sources as the scene file has them.
    scene_sources: Vec<WindSource>,
    /// The scene's inflow, None without one.
    scene_inflow: Option<Inflow>,
    /// The inflow's speed now (its sign as the scene's), None without an inflow.
    pub inflow: Option<f32>,
    /// The scene's sources' strength times this (no inflow: the up and
    /// down arrows act on them).
    pub strength_scale: f32,
    /// Degrees anticlockwise (seen from above, +x towards -z) from the
    /// scene's inflow direction (+x without an inflow).
    pub heading_deg: f32,
    gusts: Vec<WindSource>,
}

impl WindControls {
    pub fn new(scene: &Scene) -> Self {
        Self {
            scene_sources: scene.wind.sources.clone(),
            scene_inflow: scene.wind.inflow,
            inflow: scene.wind.inflow.map(|i| i.speed),
            strength_scale: 1.0,
            heading_deg: 0.0,
            gusts: Vec::new(),
        }
    }

    /// Up (`steps` > 0) or down: the inflow's speed, keeping its side, or
    /// the sources' strength where there is no inflow.
    pub fn strengthen(&mut self, steps: i32) {
        match self.inflow.as_mut() {
            Some(speed) => {
                let magnitude = (speed.abs() + steps as f32 * SPEED_STEP).clamp(0.0, MAX_INFLOW);
                *speed = magnitude.copysign(*speed);
            }
            None => {
                self.strength_scale =
                    (self.strength_scale * STRENGTH_STEP.powi(steps)).clamp(1.0 / 64.0, 64.0)
            }
        }
    }

    pub fn turn(&mut self, steps: i32) {
        self.heading_deg = (self.heading_deg + steps as f32 * TURN_STEP_DEG).rem_euclid(360.0);
    }

    /// The horizontal unit vector the heading points along.
    pub fn heading(&self) -> Vec3 {
        let base = match &self.scene_inflow {
            Some(i) => {
                let [c, s] = i.heading_vector();
                Vec3::new(c, 0.0, s) * if i.speed < 0.0 { -1.0 } else { 1.0 }
            }
            None => Vec3::X,
        };
        turned_about_y(base, self.heading_deg.to_radians())
    }

    /// The inflow now: the scene's, at the keys' speed, turned by the
    /// heading (an inflow's heading grows from +x towards +z, the keys'
    /// from +x towards -z).
    pub fn inflow_now(&self) -> Option<Inflow> {
        let (scene, speed) = (self.scene_inflow?, self.inflow?);
        Some(Inflow {
            speed,
            heading: (scene.heading - self.heading_deg).rem_euclid(360.0),
            ..scene
        })
    }

    /// Drops a gust centred `GUST_HEIGHT` above `ground`, blowing along the
    /// heading from simulated time `now` for `GUST_SECONDS`.
    pub fn drop_gust(&mut self, ground: Vec3, now: f32) {
        self.gusts
            .retain(|g| g.off_after.is_some_and(|off| off > now));
        if self.gusts.len() == MAX_GUSTS {
            self.gusts.remove(0);
        }
        let mut gust = WindSource::fixed(
            ground + Vec3::Y * GUST_HEIGHT,
            self.heading(),
            GUST_STRENGTH,
            GUST_RADIUS,
        );
        gust.off_after = Some(now + GUST_SECONDS);
        self.gusts.push(gust);
    }

    /// Gusts still blowing at `now`.
    pub fn gusts_blowing(&self, now: f32) -> usize {
        self.gusts
            .iter()
            .filter(|g| g.off_after.is_some_and(|off| off > now))
            .count()
    }

    /// What drives the wind: the inflow and every source, the scene's
    /// turned by the heading and scaled, then the gusts.
    pub fn drive(&self) -> (Option<Inflow>, Vec<WindSource>) {
        let angle = self.heading_deg.to_radians();
        let mut sources: Vec<WindSource> = self
            .scene_sources
            .iter()
            .map(|s| {
                let mut s = s.clone();
                s.direction = turned_about_y(s.direction, angle);
                s.strength *= self.strength_scale;
                s
            })
            .collect();
        sources.extend(self.gusts.iter().cloned());
        (self.inflow_now(), sources)
    }
}

/// The point of the ground seen at pixel (`x`, `y`) of a frame of `size`
/// pixels, for the camera `scene` has at `time`; None where the pixel
/// looks above the horizon (or over every hill in reach).
pub fn ground_point(
    scene: &Scene,
    size: (u32, u32),
    (x, y): (f32, f32),
    time: f32,
) -> Option<Vec3> {
    let (w, h) = (size.0.max(1) as f32, size.1.max(1) as f32);
    let inverse = view_projection(scene, w / h, time).inverse();
    // Vulkan clip space: y points down, depth 0 (near) to 1 (far).
    let ndc = (2.0 * x / w - 1.0, 2.0 * y / h - 1.0);
    let unproject = |depth: f32| {
        let p: Vec4 = inverse * Vec4::new(ndc.0, ndc.1, depth, 1.0);
        p.truncate() / p.w
    };
    let (near, far) = (unproject(0.0), unproject(1.0));
    let terrain = scene.ground.terrain();
    if terrain.is_flat() {
        return flat_ground_point(near, far);
    }
    terrain_point(&terrain, near, far)
}

/// Where the ray from `near` to `far` meets the plane y = 0.
fn flat_ground_point(near: Vec3, far: Vec3) -> Option<Vec3> {
    let ray = far - near;
    if ray.y >= 0.0 || near.y <= 0.0 {
        return None;
    }
    let t = -near.y / ray.y;
    (t <= 1.0).then(|| near + ray * t)
}

/// Along the ray from `near` to `far`, the first point at or under the
/// ground `terrain` raises: marched in steps of `TERRAIN_MARCH` metres,
/// then halved down to f32's precision between the last step above and the
/// first under. A ridge thinner than a step can be missed; a pick only
/// needs the ground a person sees.
fn terrain_point(terrain: &Terrain, near: Vec3, far: Vec3) -> Option<Vec3> {
    let ray = far - near;
    let above = |t: f32| {
        let p = near + ray * t;
        p.y - terrain.height(p.x, p.z)
    };
    if above(0.0) <= 0.0 {
        return None;
    }
    let steps = (ray.length() / TERRAIN_MARCH).ceil().clamp(1.0, 1e6) as u32;
    let under = (1..=steps).find(|&i| above(i as f32 / steps as f32) <= 0.0)?;
    let (mut lo, mut hi) = (
        (under - 1) as f32 / steps as f32,
        under as f32 / steps as f32,
    );
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if above(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(near + ray * hi)
}

/// The step (m) `terrain_point` marches along a ray.
const TERRAIN_MARCH: f32 = 0.25;

#[cfg(test)]
mod tests {
    use super::*;

    /// `p`, seen through `view_proj` in a frame of `w` x `h` pixels, lies
    /// within 0.05 pixels of `pixel`.
    fn projects_back(view_proj: glam::Mat4, (w, h): (u32, u32), p: Vec3, pixel: (f32, f32)) {
        let clip = view_proj * p.extend(1.0);
        let back = (
            (clip.x / clip.w + 1.0) * 0.5 * w as f32,
            (clip.y / clip.w + 1.0) * 0.5 * h as f32,
        );
        assert!(
            (back.0 - pixel.0).abs() < 0.05 && (back.1 - pixel.1).abs() < 0.05,
            "{pixel:?} -> {p} -> {back:?}"
        );
    }

    #[test]
    fn a_ground_point_projects_back_to_the_pixel_it_was_found_at() {
        let scene = Scene::builtin("table1").unwrap();
        let (w, h) = (640u32, 360u32);
        let view_proj = view_projection(&scene, w as f32 / h as f32, 0.0);
        for pixel in [(320.0, 300.0), (40.5, 250.0), (600.0, 359.0)] {
            let p = ground_point(&scene, (w, h), pixel, 0.0).expect("below the horizon");
            assert!(p.y.abs() < 1e-3, "{p}");
            projects_back(view_proj, (w, h), p, pixel);
        }
        // The top row looks at the sky.
        assert_eq!(ground_point(&scene, (w, h), (320.0, 0.0), 0.0), None);
    }

    /// Over hills the point seen is on the ground as the terrain raises it
    /// (not on the plane under it), the first the ray meets, and projects
    /// back to its pixel.
    #[test]
    fn over_hills_the_ground_point_is_the_first_the_ray_meets_on_the_ground() {
        let scene = Scene::builtin("hills").unwrap();
        let terrain = scene.ground.terrain();
        assert!(!terrain.is_flat());
        let (w, h) = (640u32, 360u32);
        let view_proj = view_projection(&scene, w as f32 / h as f32, 0.0);
        let eye = Vec3::from(scene.camera.position);
        let mut raised = 0.0f32;
        for pixel in [
            (320.0, 300.0),
            (40.5, 250.0),
            (600.0, 359.0),
            (320.0, 200.0),
        ] {
            let Some(p) = ground_point(&scene, (w, h), pixel, 0.0) else {
                continue;
            };
            let ground = terrain.height(p.x, p.z);
            assert!((p.y - ground).abs() < 1e-3, "{p} over ground {ground}");
            raised = raised.max(ground.abs());
            // Nothing of the ground stands between the eye and it.
            for i in 1..200 {
                let q = eye.lerp(p, i as f32 / 200.0);
                assert!(
                    q.y > terrain.height(q.x, q.z) - 1e-3,
                    "{q} under the ground before {p}"
                );
            }
            projects_back(view_proj, (w, h), p, pixel);
        }
        assert!(raised > 0.1, "no pixel saw a hill: {raised} m");
    }

    #[test]
    fn the_arrows_strengthen_the_inflow_on_its_side_and_turn_the_gusts() {
        let mut scene = Scene::builtin("table1").unwrap();
        let mut c = WindControls::new(&scene);
        let start = c.inflow.unwrap();
        c.strengthen(2);
        assert_eq!(c.inflow, Some(start + 2.0 * SPEED_STEP));
        c.strengthen(-1000);
        assert_eq!(c.inflow, Some(0.0));
        c.strengthen(1000);
        assert_eq!(c.inflow, Some(MAX_INFLOW));
        // An inflow entering at the far side stays there.
        scene.wind.inflow.as_mut().unwrap().speed = -2.0;
        let mut back = WindControls::new(&scene);
        back.strengthen(1);
        assert_eq!(back.inflow, Some(-2.5));
        assert!(back.heading().abs_diff_eq(Vec3::NEG_X, 1e-6));

        c.turn(6); // 90 degrees anticlockwise from +x, seen from above: -z
        assert!(
            c.heading().abs_diff_eq(Vec3::NEG_Z, 1e-6),
            "{}",
            c.heading()
        );
        // The inflow turns with it: towards 270 degrees, which is -z.
        let inflow = c.inflow_now().unwrap();
        assert_eq!(inflow.heading, 270.0);
        let [x, z] = inflow.heading_vector();
        assert!(x.abs() < 1e-6 && (z + 1.0).abs() < 1e-6, "{x} {z}");
        c.drop_gust(Vec3::new(1.0, 0.0, 2.0), 3.0);
        let (_, sources) = c.drive();
        let gust = sources.last().unwrap();
        assert_eq!(gust.position, Vec3::new(1.0, GUST_HEIGHT, 2.0));
        let (_, direction, strength) = gust.at(3.0);
        assert!(direction.abs_diff_eq(Vec3::NEG_Z, 1e-6));
        assert_eq!(strength, GUST_STRENGTH);
        assert_eq!(gust.at(3.0 + GUST_SECONDS).2, 0.0, "the gust stops");
        assert_eq!(c.gusts_blowing(3.0 + GUST_SECONDS), 0);
        for i in 0..MAX_GUSTS + 3 {
            c.drop_gust(Vec3::ZERO, 4.0 + i as f32 * 0.01);
        }
        assert_eq!(c.drive().1.len(), MAX_GUSTS + scene.wind.sources.len());
    }

    #[test]
    fn without_an_inflow_the_arrows_scale_and_turn_the_scenes_sources() {
        let scene = Scene::builtin("fig11-meadow-rotating").unwrap();
        assert!(scene.wind.inflow.is_none() && !scene.wind.sources.is_empty());
        let mut c = WindControls::new(&scene);
        c.strengthen(1);
        c.turn(-6); // clockwise 90 degrees: +x becomes +z
        let (inflow, sources) = c.drive();
        assert_eq!(inflow, None);
        let (first, original) = (&sources[0], &scene.wind.sources[0]);
        assert_eq!(first.strength, original.strength * STRENGTH_STEP);
        let expected = turned_about_y(original.direction, -90f32.to_radians());
        assert!(first.direction.abs_diff_eq(expected, 1e-6));
        assert!(turned_about_y(Vec3::X, -90f32.to_radians()).abs_diff_eq(Vec3::Z, 1e-6));
    }
}
