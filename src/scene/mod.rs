//! Scenes: what grass grows where, the wind, the camera, the light, the
//! level of detail and the render settings. A scene is a TOML file
//! (docs/scenes.md); the built-in scenes are the files under `scenes/`,
//! compiled in, so a user can copy one and edit it.

pub mod check;
pub mod cover;
pub mod field;
pub mod file;
pub mod grey_png;
mod ground;

pub use ground::{Ground, SceneFiles};

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::model::collider::Collider;
use crate::model::terrain::Terrain;
use crate::model::wind::{
    Advection, Coupling, Gust, Inflow, Obstacle, PressureSolver, Turbulence, WindGrid,
    WindSettings, WindSource, DEFAULT_CANOPY_DRAG, DEFAULT_JACOBI_ITERATIONS, DEFAULT_V_CYCLES,
};
use crate::model::BladePhysics;

/// The most blades one scene may hold: beyond this the blade buffer alone
/// passes 1 GiB, and lavapipe would take hours per frame.
pub const MAX_BLADES: usize = 10_000_000;

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

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    /// What the scene shows (for a paper figure: the figure and its caption).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub caption: String,
    /// Seed of the grass field and the blades' physics.
    pub seed: u64,
    #[serde(default)]
    pub render: RenderSettings,
    pub camera: Camera,
    #[serde(default)]
    pub light: Light,
    #[serde(default)]
    pub lod: Lod,
    #[serde(default)]
    pub cull: Cull,
    #[serde(default)]
    pub ground: Ground,
    pub grass: Grass,
    #[serde(default)]
    pub wind: WindConfig,
    /// Things that move through the meadow and press the grass
    /// (`[[collider]]`; src/model/contact.rs).
    #[serde(default, rename = "collider", skip_serializing_if = "Vec::is_empty")]
    pub colliders: Vec<Collider>,
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
}

impl Default for Lod {
    fn default() -> Self {
        Self {
            enabled: true,
            close_distance: 4.0,
            far_distance: 9.0,
            levels: [20, 10, 3],
            shadow_levels: [10, 5, 3],
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
    /// left out of the colour pass.
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

/// The grass: where it grows and what blades it has.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Grass {
    #[serde(default)]
    pub shape: BladeShape,
    /// How the blades look: their colours blade by blade and clump by
    /// clump, and their light (`[grass.look]`; docs/scenes.md).
    #[serde(default)]
    pub look: Look,
    /// The blades' physical parameters (docs/method.md, grass dynamics).
    #[serde(default)]
    pub dynamics: GrassDynamics,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bunch: Vec<Bunch>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub meadow: Vec<Meadow>,
    /// Grass everywhere around the camera, made on the GPU tile by tile
    /// (`[grass.cover]`; src/model/cover.rs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cover: Option<Cover>,
}

/// Grass without edges: `density` blades a square metre in square tiles
/// out to `view_distance` around the camera, each tile's blades drawn
/// from `seed` and the tile's coordinates alone, so a tile that comes
/// back holds the same blades (src/model/cover.rs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cover {
    /// Blades per square metre (absent: `closing_density` of the scene's
    /// blade shapes, filled in when the scene is read).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f32>,
    /// How far from the camera tiles are made (m).
    pub view_distance: f32,
    /// The cover's own seed (absent: the scene's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Within this distance of the camera (m) the blades carry the
    /// paper's dynamics; beyond it, a quasi-static pose (absent: 30 m, or
    /// the view distance where that is shorter).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simulate_radius: Option<f32>,
    /// The rectangle the grass grows in (m, x by z; absent: everywhere),
    /// centred at `center`: a meadow kilometres wide made around the
    /// camera as the unbounded cover is, its blades beyond the edge left
    /// out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<[f32; 2]>,
    /// The rectangle's centre (world x, z; absent: the origin). Only
    /// with `size`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<[f32; 2]>,
}

impl Cover {
    pub const DEFAULT_SIMULATE_RADIUS: f32 = 30.0;

    /// Blades per square metre: as given, else the closing density of the
    /// default blade shapes (a scene read from a file has it filled in for
    /// its own shapes: `Grass::fill_defaults`).
    pub fn density(&self) -> f32 {
        self.density
            .unwrap_or_else(|| closing_density(&BladeShape::default()))
    }

    /// The least and greatest x and z a blade's root may have, [x0, z0,
    /// x1, z1]: a blade grows where x0 <= x < x1 and z0 <= z < z1 (half
    /// open, so two covers side by side share no blade). Without a size,
    /// every finite root.
    pub fn bounds(&self) -> [f32; 4] {
        match self.size {
            Some([w, d]) => {
                let [x, z] = self.center.unwrap_or([0.0, 0.0]);
                [x - 0.5 * w, z - 0.5 * d, x + 0.5 * w, z + 0.5 * d]
            }
            None => [f32::MIN, f32::MIN, f32::MAX, f32::MAX],
        }
    }

    /// The radius given, or the default within the view distance.
    pub fn simulate_radius(&self) -> f32 {
        self.simulate_radius
            .unwrap_or(Self::DEFAULT_SIMULATE_RADIUS.min(self.view_distance))
    }
}

/// A tuft of `count` blades within `radius` of `center` (world x, z).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Bunch {
    pub center: [f32; 2],
    pub radius: f32,
    pub count: usize,
}

/// Blades spread over a `size` (x, z) rectangle around `center`: `count` of
/// them, or `density` per square metre (exactly one of the two).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Meadow {
    pub center: [f32; 2],
    pub size: [f32; 2],
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub count: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f32>,
    /// A grey PNG over the meadow's rectangle (column 0 at its least x, row
    /// 0 at its least z), relative to the scene file, scaling its density:
    /// black leaves the ground bare, white keeps every blade.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mask: Option<ground::FileName>,
    /// The mask read (`Scene::read_files`), not part of the file.
    #[serde(skip)]
    pub mask_map: Option<std::sync::Arc<grey_png::Grey>>,
}

impl Meadow {
    /// The mask's value (0..=1) at (x, z), bilinear; 1 without a mask.
    pub fn mask_at(&self, x: f32, z: f32) -> f32 {
        let Some(m) = &self.mask_map else {
            return 1.0;
        };
        let (u, v) = (
            (x - self.center[0]) / self.size[0] + 0.5,
            (z - self.center[1]) / self.size[1] + 0.5,
        );
        crate::model::terrain::bilinear(&m.values, m.width, m.height, u, v)
    }

    /// The blade count, from `count` or from `density` times the area.
    pub fn blades(&self) -> usize {
        match (self.count, self.density) {
            (Some(n), _) => n,
            (None, Some(d)) => (d as f64 * self.size[0] as f64 * self.size[1] as f64)
                .round()
                .clamp(0.0, usize::MAX as f64) as usize,
            (None, None) => 0,
        }
    }
}

/// One patch of grass as the field generator walks them: the bunches in
/// file order, then the meadows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GrassPatch {
    Bunch {
        center: [f32; 2],
        radius: f32,
        count: usize,
    },
    Meadow {
        center: [f32; 2],
        size: [f32; 2],
        count: usize,
    },
}

impl GrassPatch {
    pub fn count(&self) -> usize {
        match *self {
            GrassPatch::Bunch { count, .. } | GrassPatch::Meadow { count, .. } => count,
        }
    }

    pub fn center(&self) -> [f32; 2] {
        match *self {
            GrassPatch::Bunch { center, .. } | GrassPatch::Meadow { center, .. } => center,
        }
    }

    /// Half extents of the patch's bounding box (x, z).
    pub fn half_extent(&self) -> [f32; 2] {
        match *self {
            GrassPatch::Bunch { radius, .. } => [radius, radius],
            GrassPatch::Meadow { size, .. } => [size[0] / 2.0, size[1] / 2.0],
        }
    }
}

/// The leaf area index (one side's leaf area over the ground's) of a
/// closed canopy: a meadow's, where a standing eye sees grass, not soil,
/// between the blades a few metres off (the gap fraction at 80 degrees
/// from the zenith, exp(-0.5 LAI / cos 80), is 6%; docs/method.md,
/// "Light in the canopy").
pub const CLOSED_CANOPY_LAI: f32 = 1.0;

/// The blades a square metre of `shape`'s blades that close the canopy:
/// `CLOSED_CANOPY_LAI` over a blade's mean area (160 for the default
/// shapes; table1's meadow has 222).
pub fn closing_density(shape: &BladeShape) -> f32 {
    CLOSED_CANOPY_LAI / shape.mean_area()
}

impl BladeShape {
    /// A blade's mean one-sided area (m^2): mean height times mean width
    /// times 2/3, the mean of the taper sqrt(1 - v) the geometry stage
    /// gives it (glsl/blade/blade.geom).
    pub fn mean_area(&self) -> f32 {
        let h = 0.5 * (self.height[0] + self.height[1]);
        let w = 0.5 * (self.width[0] + self.width[1]);
        h * w * (2.0 / 3.0)
    }
}

impl Grass {
    /// Fills in what a scene file may leave out and depends on other
    /// tables: the cover's density from the blade shapes.
    pub fn fill_defaults(&mut self) {
        let closing = closing_density(&self.shape);
        if let Some(cover) = &mut self.cover {
            cover.density.get_or_insert(closing);
        }
    }

    pub fn patches(&self) -> Vec<GrassPatch> {
        let bunches = self.bunch.iter().map(|b| GrassPatch::Bunch {
            center: b.center,
            radius: b.radius,
            count: b.count,
        });
        let meadows = self.meadow.iter().map(|m| GrassPatch::Meadow {
            center: m.center,
            size: m.size,
            count: m.blades(),
        });
        bunches.chain(meadows).collect()
    }

    pub fn blade_count(&self) -> usize {
        self.bunch.iter().map(|b| b.count).sum::<usize>()
            + self.meadow.iter().map(Meadow::blades).sum::<usize>()
    }
}

/// How blade shapes are drawn: the mix of kinds (relative weights) and the
/// ranges of height and full width, in metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BladeShape {
    pub upright: f32,
    pub curved: f32,
    pub drooping: f32,
    pub height: [f32; 2],
    pub width: [f32; 2],
}

impl Default for BladeShape {
    fn default() -> Self {
        Self {
            upright: 0.4,
            curved: 0.4,
            drooping: 0.2,
            height: [0.35, 0.75],
            width: [0.012, 0.022],
        }
    }
}

/// How the blades look (ours; glsl/common/grass_color.glsl and
/// glsl/blade/blade.frag): each blade's colour from the grass texture,
/// varied by its own random number and its clump's, all drawn from the
/// scene's seed; and the strength of the leaf's sheen and translucency
/// (1: the leaf optics of docs/method.md). The defaults are a summer
/// meadow.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Look {
    /// How far blades differ in hue, fresher (bluer) to yellower green,
    /// 0..=1.
    pub hue: f32,
    /// The share of the blades that are dry (straw), 0..=1.
    pub dryness: f32,
    /// How far the tips dry and pale, 0..=1 (up to 35% of a blade).
    pub tip: f32,
    /// The clumps' size (m): blades grow in clumps of about this
    /// spacing that differ in shade (0: no clumps), 0..=10.
    pub clump_size: f32,
    /// How far clumps differ in hue and lightness, 0..=1.
    pub clump_variation: f32,
    /// The cuticle's sheen (specular), times the leaf optics', 0..=4.
    pub sheen: f32,
    /// The light through a blade lit from behind, times the leaf
    /// optics', 0..=4.
    pub translucency: f32,
    /// The canopy's shade of its own lower part (Beer-Lambert over the
    /// leaf area above a point): on, or off.
    pub self_shadowing: bool,
}

impl Default for Look {
    fn default() -> Self {
        Self {
            hue: 0.5,
            dryness: 0.04,
            tip: 0.4,
            clump_size: 0.5,
            clump_variation: 0.5,
            sheen: 1.0,
            translucency: 1.0,
            self_shadowing: true,
        }
    }
}

/// The grass's physical parameters, which the paper does not give (ours):
/// every blade draws each one uniformly from its [min, max] range, seeded,
/// so that no two blades sway in step. Defaults give a bending frequency of
/// about 1-2 Hz and a tip-edge deflection of about 0.3 rad in a 2.5 m/s wind
/// for the default blade shapes (docs/architecture.md, "Grass dynamics").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GrassDynamics {
    /// Mass of each edge (kg).
    pub edge_mass: [f32; 2],
    /// Drag coefficient sigma of W = S sigma v (N s / m^3).
    pub sigma: [f32; 2],
    /// Stiffness of the tip edge, k_tip (N / rad).
    pub tip_stiffness: [f32; 2],
    /// k_root / k_tip (>= 1): how much stiffer the root edge is.
    pub stiffness_ratio: [f32; 2],
    /// Damping as a fraction of critical damping (0: none, 1: critical).
    pub damping_ratio: [f32; 2],
}

impl Default for GrassDynamics {
    fn default() -> Self {
        Self {
            edge_mass: [3e-4, 6e-4],
            sigma: [0.08, 0.14],
            tip_stiffness: [5e-3, 9e-3],
            stiffness_ratio: [3.0, 5.0],
            damping_ratio: [0.15, 0.3],
        }
    }
}

impl GrassDynamics {
    /// The named ranges, in file order.
    pub fn ranges(&self) -> [(&'static str, [f32; 2]); 5] {
        [
            ("edge_mass", self.edge_mass),
            ("sigma", self.sigma),
            ("tip_stiffness", self.tip_stiffness),
            ("stiffness_ratio", self.stiffness_ratio),
            ("damping_ratio", self.damping_ratio),
        ]
    }

    /// The corners of the ranges as blade parameters.
    pub fn corners(&self) -> [BladePhysics; 2] {
        std::array::from_fn(|i| BladePhysics {
            edge_mass: self.edge_mass[i],
            sigma: self.sigma[i],
            tip_stiffness: self.tip_stiffness[i],
            stiffness_ratio: self.stiffness_ratio[i],
            damping_ratio: self.damping_ratio[i],
        })
    }

    /// Rejects ranges that are reversed or allow a bad blade (zero mass,
    /// negative stiffness, NaN), naming the parameter.
    pub fn validate(&self) -> Result<()> {
        check::dynamics(self).map_err(|e| e.at("grass.dynamics").into())
    }
}

/// The wind of a scene (docs/method.md section 3): the grid spans the grass's
/// bounding box plus a margin, from the ground up to `height`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WindConfig {
    /// Cells along x, y (up), z: the paper's grid is 60 x 20 x 60.
    pub cells: [u32; 3],
    /// Height of the air the grid covers (m).
    pub height: f32,
    /// Horizontal margin around the grass (m).
    pub margin: f32,
    /// With `[grass.cover]`: the grid's horizontal extent [x, z] (m),
    /// centred under the camera, instead of the grass's box.
    #[serde(skip_serializing_if = "WindConfig::is_default_window")]
    pub window: [f32; 2],
    /// How the projection solves for the pressure: "multigrid" (default,
    /// converges) or "jacobi" (the paper's).
    pub solver: PressureSolver,
    /// Jacobi iterations per step with `solver = "jacobi"` (the paper's
    /// count is not given; 30 by default, docs/physics.md on what they reach).
    pub jacobi_iterations: u32,
    /// Multigrid V-cycles per step with `solver = "multigrid"`.
    pub v_cycles: u32,
    /// "one-way" (the paper's: the grass never touches the wind) or
    /// "two-way" (the canopy drag -C_d a |u| u slows the air in the grass).
    pub coupling: Coupling,
    /// C_d of the canopy drag with two-way coupling.
    pub canopy_drag: f32,
    /// "maccormack" (default: second order, bounded, keeps gusts) or
    /// "semi-lagrangian" (the paper's first-order step).
    pub advection: Advection,
    /// `{ intensity, length_scale, seed }`: a fluctuating wind everywhere
    /// (src/model/turbulence.rs); absent: none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub turbulence: Option<Turbulence>,
    /// Simulation step (s); the frame rate never changes it.
    pub dt: f32,
    #[serde(rename = "source", skip_serializing_if = "Vec::is_empty")]
    pub sources: Vec<WindSource>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub inflow: Option<Inflow>,
    #[serde(rename = "obstacle", skip_serializing_if = "Vec::is_empty")]
    pub obstacles: Vec<Obstacle>,
}

impl Default for WindConfig {
    /// The paper's grid, still air.
    fn default() -> Self {
        Self {
            cells: [60, 20, 60],
            height: 3.0,
            margin: 1.5,
            window: DEFAULT_WIND_WINDOW,
            solver: PressureSolver::default(),
            jacobi_iterations: DEFAULT_JACOBI_ITERATIONS,
            v_cycles: DEFAULT_V_CYCLES,
            coupling: Coupling::default(),
            canopy_drag: DEFAULT_CANOPY_DRAG,
            advection: Advection::default(),
            turbulence: None,
            dt: 1.0 / 60.0,
            sources: Vec::new(),
            inflow: None,
            obstacles: Vec::new(),
        }
    }
}

/// `wind.window`'s default (m): a 40 x 40 m square under the camera.
pub const DEFAULT_WIND_WINDOW: [f32; 2] = [40.0, 40.0];

impl WindConfig {
    fn is_default_window(window: &[f32; 2]) -> bool {
        *window == DEFAULT_WIND_WINDOW
    }

    /// Wind from the left (paper Fig. 10): a gusting inflow along +x.
    pub fn from_the_left(speed: f32) -> Self {
        Self {
            inflow: Some(Inflow {
                speed,
                heading: 0.0,
                gust: Gust {
                    amplitude: 0.5,
                    frequency: 0.3,
                    seed: 1,
                },
            }),
            ..Self::default()
        }
    }

    /// What drives the wind, but the colliders (which the scene holds
    /// beside its wind: `Scene::wind_settings`).
    pub fn settings(&self) -> WindSettings {
        WindSettings {
            sources: self.sources.clone(),
            inflow: self.inflow,
            obstacles: self.obstacles.clone(),
            colliders: Vec::new(),
            solver: self.solver,
            jacobi_iterations: self.jacobi_iterations,
            v_cycles: self.v_cycles,
            coupling: self.coupling,
            canopy_drag: self.canopy_drag,
            advection: self.advection,
            turbulence: self.turbulence,
            terrain: Default::default(),
            moving_window: false,
        }
    }
}

/// The built-in scenes: the files under `scenes/`, compiled in.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "fig10-few-bunches",
        include_str!("../../scenes/fig10-few-bunches.toml"),
    ),
    (
        "fig10-several-bunches",
        include_str!("../../scenes/fig10-several-bunches.toml"),
    ),
    (
        "fig11-meadow-rotating",
        include_str!("../../scenes/fig11-meadow-rotating.toml"),
    ),
    ("fig12-lod", include_str!("../../scenes/fig12-lod.toml")),
    (
        "fig13-obstacles",
        include_str!("../../scenes/fig13-obstacles.toml"),
    ),
    ("table1", include_str!("../../scenes/table1.toml")),
    ("gust-strip", include_str!("../../scenes/gust-strip.toml")),
    ("prairie", include_str!("../../scenes/prairie.toml")),
    ("steppe", include_str!("../../scenes/steppe.toml")),
    ("roll", include_str!("../../scenes/roll.toml")),
    ("hills", include_str!("../../scenes/hills.toml")),
    ("honami", include_str!("../../scenes/honami.toml")),
];

/// A uniform draw in [0, 1) from a seed and an index (SplitMix64's
/// finaliser): the same on every machine.
fn unit_hash(seed: u64, index: u64) -> f32 {
    let mut z = seed.wrapping_add(index.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32
}

/// How far above the ground a root is tested against the obstacles: a box
/// or cylinder standing on the ground holds its footprint's roots.
const ROOT_CLEARANCE: f32 = 0.01;

/// The grass a scene grows: its blades, and how many of those its patches
/// planted were left out under the obstacles.
#[derive(Clone, Debug)]
pub struct Planted {
    pub blades: Vec<crate::model::Blade>,
    pub under_obstacles: usize,
    /// Blades the meadows' masks left out.
    pub masked: usize,
}

impl Scene {
    /// The scene's grass field (`field::generate`) rooted on the ground,
    /// without the blades whose root lies inside an obstacle: nothing grows
    /// through a wall, a boulder or a post. The patches' counts are the
    /// counts before.
    pub fn field(&self) -> Result<Vec<crate::model::Blade>> {
        Ok(self.planted()?.blades)
    }

    /// As `field`, counting the blades left out under the obstacles; a
    /// scene whose obstacles leave no blade is refused, naming them.
    pub fn planted(&self) -> Result<Planted> {
        let terrain = self.ground.terrain();
        let mut blades = field::generate(&self.grass, self.seed)?;
        let masked = self.mask_out(&mut blades);
        // A cover alone plants nothing here: its blades are made around
        // the camera on the GPU.
        if blades.is_empty() && !(self.grass.cover.is_some() && self.grass.blade_count() == 0) {
            return Err(Error::InvalidInput(format!(
                "the meadows' masks leave none of the {masked} blades planted; make a mask lighter where grass should grow"
            )));
        }
        if !terrain.is_flat() {
            // Rooted on the ground, growing upright as grass does on a
            // slope, a blade leaning into the slope turned away from it;
            // contact keeps them over the ground within their reach
            // (`Blade::ground_curvature`).
            for b in &mut blades {
                *b = terrain.root_fitted(*b);
            }
        }
        let obstacles = &self.wind.obstacles;
        let planted = blades.len();
        let mut covering = vec![false; obstacles.len()];
        if !obstacles.is_empty() {
            blades.retain(|b| {
                let root = b.rest[0] + Vec3::Y * ROOT_CLEARANCE;
                match obstacles.iter().position(|o| o.contains(root)) {
                    Some(i) => {
                        covering[i] = true;
                        false
                    }
                    None => true,
                }
            });
        }
        if blades.is_empty() && planted > 0 {
            let names: Vec<String> = (0..obstacles.len())
                .filter(|&i| covering[i])
                .map(|i| format!("wind.obstacle[{i}]"))
                .collect();
            return Err(Error::InvalidInput(format!(
                "the obstacles cover the root of every one of the {planted} blades planted ({}); move or shrink them, or move the grass",
                names.join(", ")
            )));
        }
        Ok(Planted {
            under_obstacles: planted - blades.len(),
            masked,
            blades,
        })
    }

    /// Leaves out of a masked meadow's blades (they follow the bunches'
    /// in `blades`, each patch's in one run) those whose draw, a hash of
    /// the seed and the blade's place, is not under the mask's value at
    /// its root: the density scaled by the mask, the same on every run.
    /// Returns how many it left out.
    fn mask_out(&self, blades: &mut Vec<crate::model::Blade>) -> usize {
        if self.grass.meadow.iter().all(|m| m.mask_map.is_none()) {
            return 0;
        }
        let before = blades.len();
        let mut owner = Vec::with_capacity(before);
        owner.extend(
            self.grass
                .bunch
                .iter()
                .flat_map(|b| std::iter::repeat_n(None, b.count)),
        );
        owner.extend(
            self.grass
                .meadow
                .iter()
                .flat_map(|m| std::iter::repeat_n(Some(m), m.blades())),
        );
        let mut index = 0u64;
        blades.retain(|b| {
            let meadow = owner[index as usize];
            index += 1;
            meadow.is_none_or(|m| {
                let draw = unit_hash(self.seed ^ 0x6D61_736B, index);
                draw < m.mask_at(b.rest[0].x, b.rest[0].z)
            })
        });
        before - blades.len()
    }

    /// Reads the files the scene names (the ground's height map, the
    /// meadows' masks) from `files`, after `check::scene` passed.
    pub fn read_files(&mut self, files: SceneFiles<'_>) -> check::Check {
        self.ground.read_files(files).map_err(|e| e.at("ground"))?;
        for (i, m) in self.grass.meadow.iter_mut().enumerate() {
            m.mask_map = match &mut m.mask {
                None => None,
                Some(name) => {
                    let grey = ground::read_grey(&name.written, files).map_err(|e| {
                        check::FieldError::new(format!("grass.meadow[{i}].mask"), e)
                    })?;
                    name.found_in(files);
                    Some(std::sync::Arc::new(grey))
                }
            };
        }
        Ok(())
    }

    /// A built-in scene by name.
    pub fn builtin(name: &str) -> Result<Scene> {
        let Some((_, text)) = BUILTIN.iter().find(|(n, _)| *n == name) else {
            let names: Vec<&str> = BUILTIN.iter().map(|(n, _)| *n).collect();
            let closest = names
                .iter()
                .map(|n| (strsim::damerau_levenshtein(name, n), *n))
                .min()
                .filter(|&(distance, n)| distance <= n.len().div_ceil(3).max(2));
            let guess = closest.map_or(String::new(), |(_, n)| format!("did you mean {n:?}? "));
            return Err(Error::InvalidInput(format!(
                "unknown scene {name:?}; {guess}the built-in scenes are: {} (or give a path to a .toml file)",
                names.join(", ")
            )));
        };
        file::parse_in(text, &format!("scenes/{name}.toml"), SceneFiles::Builtin)
    }

    /// `--scene`: a built-in name, or a path to a TOML file (anything
    /// ending in .toml or containing a path separator).
    pub fn load(name_or_path: &str) -> Result<Scene> {
        if name_or_path.ends_with(".toml") || name_or_path.contains(std::path::MAIN_SEPARATOR) {
            file::load(std::path::Path::new(name_or_path))
        } else {
            Self::builtin(name_or_path)
        }
    }

    /// Every check a scene must pass before anything is allocated; the
    /// error names the field (`grass.meadow[0].count`) and the allowed range.
    pub fn validate(&self) -> Result<()> {
        check::scene(self).map_err(Into::into)
    }

    pub fn blade_count(&self) -> usize {
        self.grass.blade_count()
    }

    /// Sets the total blade count, shared among the patches in proportion
    /// to their current counts (the remainder goes to the first patches).
    /// Meadows given by density get an explicit count.
    pub fn set_blade_count(&mut self, total: usize) -> Result<()> {
        if total == 0 || total > MAX_BLADES {
            return Err(Error::InvalidInput(format!(
                "--blades {total} is not allowed, use 1..={MAX_BLADES}"
            )));
        }
        let old = self.blade_count().max(1);
        let patches = self.grass.patches();
        if patches.is_empty() {
            return Err(Error::InvalidInput(format!(
                "--blades {total}: this scene's only grass is a [grass.cover], whose blades follow its density and view_distance; change those in the scene file"
            )));
        }
        if total < patches.len() {
            return Err(Error::InvalidInput(format!(
                "--blades {total} is fewer than the scene's {} patches of grass (bunches and meadows), each of which needs a blade; use at least {}",
                patches.len(),
                patches.len()
            )));
        }
        let mut counts: Vec<usize> = patches
            .iter()
            .map(|p| (p.count() as u128 * total as u128 / old as u128) as usize)
            .collect();
        // Each share is rounded down by less than one, so fewer than
        // `counts.len()` blades are left over.
        let left = total - counts.iter().sum::<usize>();
        for c in counts.iter_mut().take(left) {
            *c += 1;
        }
        let (for_bunches, for_meadows) = counts.split_at(self.grass.bunch.len());
        for (b, &c) in self.grass.bunch.iter_mut().zip(for_bunches) {
            b.count = c;
        }
        for (m, &c) in self.grass.meadow.iter_mut().zip(for_meadows) {
            m.count = Some(c);
            m.density = None;
        }
        Ok(())
    }

    /// Sets the shadow map's side from the command line (`--shadow-map`),
    /// refusing it by the flag's name.
    pub fn set_shadow_map(&mut self, side: u32) -> Result<()> {
        check::in_range("--shadow-map", side, 0..=check::MAX_IMAGE_SIDE)
            .map_err(|e| Error::InvalidInput(format!("{} {}", e.path, e.message)))?;
        self.light.shadow_map = side;
        Ok(())
    }

    /// Sets the pressure solve's Jacobi iterations from the command line
    /// (`--jacobi-iterations`), refusing it by the flag's name. Asking for
    /// Jacobi iterations picks the Jacobi solver.
    pub fn set_jacobi_iterations(&mut self, iterations: u32) -> Result<()> {
        check::in_range("--jacobi-iterations", iterations, 0..=10_000)
            .map_err(|e| Error::InvalidInput(format!("{} {}", e.path, e.message)))?;
        self.wind.jacobi_iterations = iterations;
        self.wind.solver = PressureSolver::Jacobi;
        Ok(())
    }

    /// Sets the multigrid V-cycles from the command line (`--v-cycles`),
    /// refusing it by the flag's name; picks the multigrid solver.
    pub fn set_v_cycles(&mut self, cycles: u32) -> Result<()> {
        check::in_range("--v-cycles", cycles, 1..=check::MAX_V_CYCLES)
            .map_err(|e| Error::InvalidInput(format!("{} {}", e.path, e.message)))?;
        self.wind.v_cycles = cycles;
        self.wind.solver = PressureSolver::Multigrid;
        Ok(())
    }

    /// Sets the wind grid's cells from the command line (`--cells X,Y,Z`),
    /// refusing them by the flag's name.
    pub fn set_wind_cells(&mut self, text: &str) -> Result<()> {
        let bad = |why: String| Error::InvalidInput(format!("--cells {text} {why}"));
        let cells: Vec<u32> = text
            .split(',')
            .map(|n| n.trim().parse::<u32>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| bad("is not three whole numbers X,Y,Z (y is up), e.g. 60,20,60".into()))?;
        let cells: [u32; 3] = cells
            .try_into()
            .map_err(|c: Vec<u32>| bad(format!("has {} values, use exactly 3: X,Y,Z", c.len())))?;
        let mut wind = self.wind.clone();
        wind.cells = cells;
        check::wind(&wind).map_err(|e| bad(format!("({}) {}", e.path, e.message)))?;
        self.wind.cells = cells;
        Ok(())
    }

    /// `grass_bounds` grown by the tallest blade: where any part of a
    /// blade can reach, leaning as far as it can (x, z).
    pub fn grass_reach_bounds(&self) -> ([f32; 2], [f32; 2]) {
        let (lo, hi) = self.grass_bounds();
        let h = self.grass.shape.height[1];
        ([lo[0] - h, lo[1] - h], [hi[0] + h, hi[1] + h])
    }

    /// Bounding box (x, z) of where the grass grows: (min, max). A cover
    /// grows within its view distance of every camera position the scene
    /// gives (its position and its path's keys), and a bounded cover
    /// within its rectangle too.
    pub fn grass_bounds(&self) -> ([f32; 2], [f32; 2]) {
        let mut lo = [f32::MAX; 2];
        let mut hi = [f32::MIN; 2];
        let mut grow = |c: [f32; 2], half: [f32; 2]| {
            for a in 0..2 {
                lo[a] = lo[a].min(c[a] - half[a]);
                hi[a] = hi[a].max(c[a] + half[a]);
            }
        };
        for p in self.grass.patches() {
            grow(p.center(), p.half_extent());
        }
        if let Some(cover) = &self.grass.cover {
            let d = cover.view_distance;
            let [x0, z0, x1, z1] = cover.bounds();
            for p in self.camera_positions() {
                // The camera's square of tiles, within the bounds.
                let (a, b) = (
                    [(p.x - d).max(x0), (p.z - d).max(z0)],
                    [(p.x + d).min(x1), (p.z + d).min(z1)],
                );
                if a[0] <= b[0] && a[1] <= b[1] {
                    // Its corners as they are (no centre and half to
                    // round): an unbounded cover's box is what it was.
                    for axis in 0..2 {
                        lo[axis] = lo[axis].min(a[axis]);
                        hi[axis] = hi[axis].max(b[axis]);
                    }
                }
            }
        }
        (lo, hi)
    }

    /// The camera's position and its path's keys' positions.
    pub fn camera_positions(&self) -> impl Iterator<Item = Vec3> + '_ {
        let c = &self.camera;
        std::iter::once(Vec3::from(c.position)).chain(c.path.iter().map(|k| Vec3::from(k.position)))
    }

    /// Everything that drives the scene's wind: its `[wind]`, the
    /// colliders, which push the air as they move, and the ground it
    /// blows over.
    pub fn wind_settings(&self) -> WindSettings {
        WindSettings {
            colliders: self.colliders.clone(),
            terrain: self.ground.terrain(),
            moving_window: self.grass.cover.is_some(),
            ..self.wind.settings()
        }
    }

    /// The wind grid: the grass's bounding box plus the margin, from the
    /// lowest ground under it to `height` above the highest (flat: 0 to
    /// `height`). Refuses a grid that leaves less than one cell of air
    /// over the highest ground.
    pub fn wind_grid(&self) -> Result<WindGrid> {
        let w = &self.wind;
        check::wind(w).map_err(|e| e.at("wind"))?;
        let (lo, hi) = match &self.grass.cover {
            // The window under the camera where the scene starts.
            Some(_) => {
                let (eye, _) = self.camera.at(0.0);
                let half = [0.5 * w.window[0], 0.5 * w.window[1]];
                (
                    [eye.x - half[0], eye.z - half[1]],
                    [eye.x + half[0], eye.z + half[1]],
                )
            }
            None => {
                let (lo, hi) = self.grass_bounds();
                (
                    [lo[0] - w.margin, lo[1] - w.margin],
                    [hi[0] + w.margin, hi[1] + w.margin],
                )
            }
        };
        let terrain = self.ground.terrain();
        let (grid, size) = if self.cover_on_terrain() {
            // A window over terrain stands in the world's heights, its
            // floor and lid fixed for every place the camera's path takes
            // it (the ground's staircase moves through it).
            let (reach_lo, reach_hi) = self.window_reach();
            let (reach, size) = self.grid_over_ground(&terrain, reach_lo, reach_hi)?;
            let size = Vec3::new(hi[0] - lo[0], size.y, hi[1] - lo[1]);
            let origin = Vec3::new(lo[0], reach.origin.y, lo[1]);
            (WindGrid::new(reach.cells, origin, size)?, size)
        } else {
            self.grid_over_ground(&terrain, lo, hi)?
        };
        if let Some(t) = &w.turbulence {
            let (cell, side) = (grid.cell.max_element(), size.max_element());
            if !(cell..=side).contains(&t.length_scale) {
                return Err(Error::InvalidInput(format!(
                    "wind.turbulence.length_scale {} m is not allowed on this wind grid, use {cell:.2}..={side:.1} m: from its largest cell side (smaller eddies cannot be held) to its largest side",
                    t.length_scale
                )));
            }
        }
        Ok(grid)
    }

    /// The wind grid over `lo`..`hi` (x, z), from the lowest ground there
    /// to `wind.height` over the highest, and its size.
    fn grid_over_ground(
        &self,
        terrain: &Terrain,
        lo: [f32; 2],
        hi: [f32; 2],
    ) -> Result<(WindGrid, Vec3)> {
        let w = &self.wind;
        let span = [hi[0] - lo[0], hi[1] - lo[1]];
        // A quarter of a wind cell between the heights looked at.
        let step = (span[0] / w.cells[0] as f32).min(span[1] / w.cells[2] as f32) / 4.0;
        let (low, high) = terrain.range_over(lo, hi, step.max(1e-3));
        let origin = Vec3::new(lo[0], low, lo[1]);
        let size = Vec3::new(span[0], high - low + w.height, span[1]);
        let cell_height = size.y / w.cells[1] as f32;
        if w.height < cell_height {
            return Err(Error::InvalidInput(format!(
                "wind.height {} m leaves less than one wind cell ({cell_height:.2} m tall) of air over the ground's highest point ({high:.2} m, {:.2} m above its lowest); raise wind.height or wind.cells[1]",
                w.height,
                high - low
            )));
        }
        let grid = WindGrid::new(glam::UVec3::from(w.cells), origin, size)?;
        Ok((grid, size))
    }

    /// The rectangle (x, z) a cover's wind window may cover: `wind.window`
    /// around every place the camera is and its path goes (straight
    /// between its keys).
    fn window_reach(&self) -> ([f32; 2], [f32; 2]) {
        let half = [0.5 * self.wind.window[0], 0.5 * self.wind.window[1]];
        let (mut lo, mut hi) = ([f32::MAX; 2], [f32::MIN; 2]);
        for p in self.camera_positions() {
            for (axis, v) in [p.x, p.z].into_iter().enumerate() {
                lo[axis] = lo[axis].min(v - half[axis]);
                hi[axis] = hi[axis].max(v + half[axis]);
            }
        }
        (lo, hi)
    }

    /// Whether the scene's grass is a `[grass.cover]` over terrain: its
    /// wind window's floor and lid then hold the ground along the camera's
    /// path, and its terrain mesh follows the camera.
    pub fn cover_on_terrain(&self) -> bool {
        self.grass.cover.is_some() && !self.ground.terrain().is_flat()
    }

    /// Centre of the grass (x, z), for the ground square.
    pub fn grass_center(&self) -> Vec3 {
        let patches = self.grass.patches();
        let n = patches.len().max(1) as f32;
        let sum = patches.iter().fold(Vec3::ZERO, |acc, p| {
            let c = p.center();
            acc + Vec3::new(c[0], 0.0, c[1])
        });
        sum / n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cover's window over terrain stands in the world's heights: its
    /// floor under the lowest ground and its lid `wind.height` over the
    /// highest wherever the camera's path takes it (steppe's kilometre:
    /// hills, ridges and a hollow), centred under the camera where it
    /// starts. Its cells keep `wind.cells`.
    #[test]
    fn a_covers_window_over_terrain_holds_the_ground_along_the_cameras_path() {
        let scene = Scene::builtin("steppe").unwrap();
        let grid = scene.wind_grid().unwrap();
        let terrain = scene.ground.terrain();
        let (floor, lid) = (grid.origin.y, grid.origin.y + grid.size().y);
        let half = grid.size() / 2.0;
        let (eye, _) = scene.camera.at(0.0);
        assert!((grid.origin.x + half.x - eye.x).abs() < 1e-3, "{grid:?}");
        assert!((grid.origin.z + half.z - eye.z).abs() < 1e-3, "{grid:?}");
        assert_eq!(grid.cells.to_array(), scene.wind.cells);
        for p in scene.camera_positions() {
            let (low, high) = terrain.range_over(
                [p.x - half.x, p.z - half.z],
                [p.x + half.x, p.z + half.z],
                0.5,
            );
            assert!(
                floor <= low + 1e-3,
                "at {p}: the ground at {low} under the floor {floor}"
            );
            assert!(
                lid + 1e-3 >= high + scene.wind.height,
                "at {p}: the lid {lid} less than wind.height over the ground's {high}"
            );
        }
        eprintln!("steppe's window: {grid:?}");
    }

    #[test]
    fn blades_under_obstacles_are_counted() {
        let scene = Scene::builtin("fig13-obstacles").unwrap();
        let planted = scene.planted().unwrap();
        assert!(planted.under_obstacles > 0);
        assert_eq!(
            planted.blades.len() + planted.under_obstacles,
            scene.blade_count()
        );
        let mut open = scene.clone();
        open.wind.obstacles.clear();
        assert_eq!(open.planted().unwrap().under_obstacles, 0);
    }

    #[test]
    fn obstacles_leaving_no_blade_are_refused_by_name() {
        let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
        scene.wind.obstacles = vec![
            crate::model::wind::Obstacle::Box {
                min: Vec3::new(50.0, 0.0, 50.0),
                max: Vec3::new(51.0, 1.0, 51.0),
            },
            crate::model::wind::Obstacle::Box {
                min: Vec3::new(-100.0, 0.0, -100.0),
                max: Vec3::new(100.0, 1.0, 100.0),
            },
        ];
        let e = scene.planted().unwrap_err().to_string();
        assert!(
            e.contains("cover the root of every one") && e.contains("(wind.obstacle[1])"),
            "{e}"
        );
    }

    #[test]
    fn blade_count_is_shared_exactly() {
        let mut s = Scene::builtin("fig10-several-bunches").unwrap();
        for total in [9, 10, 1000, 12345] {
            s.set_blade_count(total).unwrap();
            assert_eq!(s.blade_count(), total);
        }
        // Fewer blades than its 9 bunches would leave a bunch empty.
        for total in [1, 8] {
            let e = s.set_blade_count(total).unwrap_err().to_string();
            assert!(e.contains("fewer than the scene's 9 patches"), "{e}");
        }
        assert!(s.set_blade_count(0).is_err());
        assert!(s.set_blade_count(MAX_BLADES + 1).is_err());
    }

    #[test]
    fn unknown_scene_names_the_choices() {
        let e = Scene::builtin("nope").unwrap_err().to_string();
        assert!(e.contains("unknown scene") && e.contains("table1"), "{e}");
        let e = Scene::builtin("tabel1").unwrap_err().to_string();
        assert!(e.contains("did you mean \"table1\"?"), "{e}");
        let e = Scene::builtin("fig10-few-bunch").unwrap_err().to_string();
        assert!(e.contains("did you mean \"fig10-few-bunches\"?"), "{e}");
        let e = Scene::builtin("sunset").unwrap_err().to_string();
        assert!(!e.contains("did you mean"), "{e}");
    }

    #[test]
    fn camera_path_interpolates_and_holds_its_ends() {
        let key = |time: f32, x: f32| CameraKey {
            time,
            position: [x, 1.0, 0.0],
            target: [0.0; 3],
        };
        let camera = Camera {
            position: [9.0; 3],
            target: [0.0; 3],
            fov_y: 45.0,
            path: vec![key(1.0, 0.0), key(3.0, 4.0)],
        };
        assert_eq!(camera.at(0.0).0.x, 0.0);
        assert_eq!(camera.at(2.0).0.x, 2.0);
        assert_eq!(camera.at(5.0).0.x, 4.0);
        let still = Camera {
            path: Vec::new(),
            ..camera
        };
        assert_eq!(still.at(2.0).0, Vec3::splat(9.0));
    }

    #[test]
    fn meadow_density_gives_count() {
        let m = Meadow {
            center: [0.0; 2],
            size: [2.0, 3.0],
            count: None,
            density: Some(100.0),
            mask: None,
            mask_map: None,
        };
        assert_eq!(m.blades(), 600);
    }
}
