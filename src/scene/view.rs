//! The scene's view sections, each type beside its check: `[render]`,
//! `[camera]`, `[light]`, `[lod]`, `[cull]`. They use the checks' helpers
//! (check.rs) and nothing else of the scene.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::check::{
    finite, in_range, positive, within, Check, FieldError, MAX_FRAMES, MAX_IMAGE_SIDE,
};

/// What the fragment stage shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ViewMode {
    /// The lit, coloured grass.
    #[default]
    Shaded,
    /// Blades coloured by tessellation level: red 20, yellow 10, blue 3.
    Lod,
    /// Blades coloured by angular displacement from rest.
    Motion,
}

/// Whether a frame's simulation steps run beside the drawing of the frame
/// before (src/frame/ahead.rs): on a second queue where the device has
/// one, the simulated blades copied into the drawn ones when that frame
/// is drawn, one frame of latency between a change to the wind or the
/// colliders and the picture.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Overlap {
    /// On where the device has a second queue and the scene allows it
    /// (no `[grass.cover]`, no wind window following the camera); off
    /// otherwise.
    #[default]
    Auto,
    /// Always: on a device with one queue, the same submissions in order
    /// on it (no overlap on the GPU; the read-back of a frame overlaps the
    /// next frame's steps on the host). Refused where the scene does not
    /// allow it.
    On,
    /// One submission a frame, steps then drawing.
    Off,
}

impl std::fmt::Display for Overlap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Auto => "auto",
            Self::On => "on",
            Self::Off => "off",
        })
    }
}

/// How the scene is rendered unless the command line says otherwise.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// MSAA samples asked for; the largest supported count up to this is used.
    pub msaa: u32,
    pub view: ViewMode,
    /// Frames to render; frame f shows simulated time `start + f / fps`.
    pub frames: u32,
    pub fps: f32,
    /// Simulated seconds before the first frame (the grass starts at rest).
    pub start: f32,
    /// Measure the waves of light over the frames (report.json's
    /// `light_waves`; `meadow render --light-waves`) when three or more
    /// are written.
    pub light_waves: bool,
    /// The simulation beside the drawing (`Overlap`).
    pub overlap: Overlap,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 1280,
            height: 720,
            msaa: 8,
            view: ViewMode::Shaded,
            frames: 1,
            fps: 30.0,
            start: 0.0,
            light_waves: false,
            overlap: Overlap::Auto,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    pub position: [f32; 3],
    pub target: [f32; 3],
    /// Vertical field of view in degrees.
    pub fov_y: f32,
    /// Optional keyframes: the camera moves linearly between them in
    /// simulated time, and holds the first and last beyond them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub path: Vec<CameraKey>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraKey {
    /// Simulated time (s).
    pub time: f32,
    pub position: [f32; 3],
    pub target: [f32; 3],
}

impl Camera {
    /// Position and target at simulated time `t`.
    pub fn at(&self, t: f32) -> (Vec3, Vec3) {
        let key = |k: &CameraKey| (Vec3::from(k.position), Vec3::from(k.target));
        let (Some(first), Some(last)) = (self.path.first(), self.path.last()) else {
            return (Vec3::from(self.position), Vec3::from(self.target));
        };
        if t <= first.time {
            return key(first);
        }
        for pair in self.path.windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            if t <= b.time {
                let f = (t - a.time) / (b.time - a.time);
                let (pa, ta) = key(a);
                let (pb, tb) = key(b);
                return (pa.lerp(pb, f), ta.lerp(tb, f));
            }
        }
        key(last)
    }
}

/// The paper's shadow map side, in texels.
pub const DEFAULT_SHADOW_MAP: u32 = 8192;

/// A directional light (the sun). Every field is optional on its own; a
/// missing one takes the default below.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Light {
    /// Direction toward the light (normalised on use).
    pub direction: [f32; 3],
    pub color: [f32; 3],
    /// Share of the light that reaches everything (0..1).
    pub ambient: f32,
    /// Side of the square shadow map in texels: the paper's 8192 by
    /// default; smaller for quick previews, 0 for no shadows.
    pub shadow_map: u32,
}

impl Default for Light {
    /// The afternoon sun of every built-in scene.
    fn default() -> Self {
        Self {
            direction: [0.45, 0.75, 0.35],
            color: [1.0, 0.96, 0.86],
            ambient: 0.28,
            shadow_map: DEFAULT_SHADOW_MAP,
        }
    }
}

/// Level of detail (paper section 5.1): tessellation level by distance.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Lod {
    pub enabled: bool,
    /// Closer than this: the close level.
    pub close_distance: f32,
    /// Closer than this (and not close): the medium level; beyond: far.
    pub far_distance: f32,
    /// Segments per blade for close, medium, far: the paper's 20, 10, 3.
    pub levels: [u32; 3],
    /// The same for the shadow pass (ours), chosen by the same distances
    /// to the camera: a blade's shadow is seen through 8192 texels over
    /// the field and a soft filter, where 10 segments of a blade bent to
    /// a 0.5 m radius depart from its curve by 0.6 mm and 5 by 2.5 mm,
    /// under a texel (about 3 mm on table1). With LOD off the shadow pass
    /// uses `levels[0]`, as the colour pass does.
    pub shadow_levels: [u32; 3],
    /// With LOD on, the shadow pass tessellates a caster no finer than
    /// its size in shadow-map texels needs (ours): its chords, its edges'
    /// turn with the twist and its tapered tip depart from the curved
    /// blade by at most this many texels (half of one by default: under
    /// what the map can hold). 0: no such bound (with
    /// `shadow_error_pixels` 0 too, the distance levels alone).
    pub shadow_error_texels: f32,
    /// ... and no finer than what the view shows of its shadow (ours):
    /// the same departures, carried by the sun to flat ground and seen
    /// across the view's rays, within this many pixels of the view where
    /// its nearest visible receiver stands (one by default: the
    /// screen-space error of level-of-detail practice). The looser of the
    /// two bounds holds: far from the camera a pixel spans many texels of
    /// the map, and a caster there needs fewer segments than its texels
    /// alone would ask. 0: the texels' bound alone.
    pub shadow_error_pixels: f32,
}

impl Default for Lod {
    fn default() -> Self {
        Self {
            enabled: true,
            close_distance: 4.0,
            far_distance: 9.0,
            levels: [20, 10, 3],
            shadow_levels: [10, 5, 3],
            shadow_error_texels: 0.5,
            shadow_error_pixels: 1.0,
        }
    }
}

/// Culling (ours; src/render/cull.rs): each frame a compute pass lists the
/// blades the colour pass can see and those whose shadow can fall into
/// the view, and each pass draws only its list. On by default; frustum and
/// shadow-caster culling leave the frames as they are without culling.
///
/// With culling on, distance thinning (glsl/common/thinning.glsl) draws a
/// share of the blades beyond `thin_from`, falling as (thin_from / d)^2 to
/// `thin_least`, and widens the blades it keeps so the far meadow keeps
/// its coverage; a blade about to be dropped narrows away over `thin_band`
/// (a share of the blades) rather than popping.
///
/// With `occlusion` (off by default), a blade in view that lies wholly
/// behind the previous frame's depth is not drawn
/// (src/render/depth_pyramid.rs); the first frame, and a frame after a
/// jump ahead in time, draws them all. A meadow is porous: through the
/// gaps between blades the depth shows the ground behind, so blades hide
/// blades almost never and the test pays only behind large opaque
/// occluders (docs/perf.md measures it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Cull {
    pub enabled: bool,
    /// Distance from the camera (m) where thinning begins; 0 turns it off.
    pub thin_from: f32,
    /// The least share of blades kept however far (their width grows by
    /// about its inverse).
    pub thin_least: f32,
    /// Width of the band over which blades narrow away, as a share of the
    /// blades kept at that distance.
    pub thin_band: f32,
    /// Orientation: a blade whose width vector lies within acos(edge_on)
    /// of the rays from the camera to it (from the sun, for the shadow
    /// pass) is seen edge-on and left out; 1 keeps every blade.
    pub edge_on: f32,
    /// Occlusion: blades hidden behind the previous frame's depth are
    /// left out of the colour pass, and blades whose shadow can fall only
    /// on what that depth hides out of the shadow pass.
    pub occlusion: bool,
}

impl Default for Cull {
    fn default() -> Self {
        Self {
            enabled: true,
            thin_from: 8.0,
            thin_least: 0.125,
            thin_band: 0.5,
            edge_on: 0.9,
            occlusion: false,
        }
    }
}

impl RenderSettings {
    pub fn check(&self) -> Check {
        in_range("width", self.width, 1..=MAX_IMAGE_SIDE)?;
        in_range("height", self.height, 1..=MAX_IMAGE_SIDE)?;
        if !self.msaa.is_power_of_two() || self.msaa > 64 {
            return Err(FieldError::new(
                "msaa",
                format!(
                    "{} is not a sample count, use 1, 2, 4, 8, 16, 32 or 64",
                    self.msaa
                ),
            ));
        }
        in_range("frames", self.frames, 1..=MAX_FRAMES)?;
        positive("fps", self.fps, 1000.0)?;
        within("start", self.start, 0.0..=86_400.0, "0..=86400 seconds")?;
        Ok(())
    }
}

impl Camera {
    pub fn check(&self) -> Check {
        let points = std::iter::once((self.position, self.target))
            .chain(self.path.iter().map(|k| (k.position, k.target)));
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
        if !(self.fov_y.is_finite() && self.fov_y > 1.0 && self.fov_y < 170.0) {
            return Err(FieldError::new(
                "fov_y",
                format!("{} is not allowed, use 1 < fov_y < 170 degrees", self.fov_y),
            ));
        }
        for (i, k) in self.path.iter().enumerate() {
            finite(&format!("path[{i}].time"), &[k.time])?;
        }
        for (i, pair) in self.path.windows(2).enumerate() {
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
}

impl Light {
    pub fn check(&self) -> Check {
        finite("direction", &self.direction)?;
        if Vec3::from(self.direction).length() < 1e-6 {
            return Err(FieldError::new(
                "direction",
                "is zero, give the direction toward the light",
            ));
        }
        if self.direction[1] < 0.0 {
            return Err(FieldError::new(
                "direction",
                format!(
                    "{:?} points below the horizon (y < 0): the light would shine up through the ground; give the direction toward the sun, y >= 0",
                    self.direction
                ),
            ));
        }
        finite("color", &self.color)?;
        if self.color.iter().any(|&c| !(0.0..=100.0).contains(&c)) {
            return Err(FieldError::new(
                "color",
                format!("{:?} is not allowed, use values in 0..=100", self.color),
            ));
        }
        in_range("shadow_map", self.shadow_map, 0..=MAX_IMAGE_SIDE)?;
        if !(0.0..=1.0).contains(&self.ambient) {
            return Err(FieldError::new(
                "ambient",
                format!("{} is not allowed, use 0..=1", self.ambient),
            ));
        }
        Ok(())
    }
}

impl Lod {
    pub fn check(&self) -> Check {
        positive("close_distance", self.close_distance, 1e6)?;
        positive("far_distance", self.far_distance, 1e6)?;
        if self.far_distance < self.close_distance {
            return Err(FieldError::new(
                "far_distance",
                format!(
                    "{} is nearer than close_distance {}; use close <= far",
                    self.far_distance, self.close_distance
                ),
            ));
        }
        for (i, &level) in self.levels.iter().enumerate() {
            in_range(&format!("levels[{i}]"), level, 1..=64)?;
        }
        for (i, &level) in self.shadow_levels.iter().enumerate() {
            in_range(&format!("shadow_levels[{i}]"), level, 1..=64)?;
        }
        within(
            "shadow_error_texels",
            self.shadow_error_texels,
            0.0..=64.0,
            "0 (no texels' bound) to 64",
        )?;
        within(
            "shadow_error_pixels",
            self.shadow_error_pixels,
            0.0..=64.0,
            "0 (the texels' bound alone) to 64",
        )?;
        Ok(())
    }
}

impl Cull {
    pub fn check(&self) -> Check {
        within(
            "thin_from",
            self.thin_from,
            0.0..=1e6,
            "0 (no thinning) or a distance up to 1e6 m",
        )?;
        within(
            "thin_least",
            self.thin_least,
            0.01..=1.0,
            "a share in 0.01..=1 (1 keeps every blade)",
        )?;
        positive("thin_band", self.thin_band, 1.0)?;
        within(
            "edge_on",
            self.edge_on,
            0.5..=1.0,
            "a cosine in 0.5..=1 (1 keeps blades seen edge-on)",
        )?;
        Ok(())
    }
}
