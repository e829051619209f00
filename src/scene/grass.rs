//! The scene's `[grass]` section, each type beside its check: the blades'
//! shape, look and dynamics, the bunches, meadows and cover. They use the
//! checks' helpers (check.rs) and the cover's blade count (cover/).

use serde::{Deserialize, Serialize};

use super::check::{
    finite, in_range, positive, range_within, within, Check, FieldError, VIEW_DISTANCE,
};
use super::MAX_BLADES;
use crate::error::Result;
use crate::model::BladePhysics;

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

/// The widest bounded cover (m) and the farthest its centre lies from
/// the origin: 100 km, where f32 roots still fall within 8 mm of where
/// the draws put them.
pub const MAX_COVER_SIZE: f32 = 100_000.0;

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
    pub mask: Option<super::ground::FileName>,
    /// The mask read (`Scene::read_files`), not part of the file.
    #[serde(skip)]
    pub mask_map: Option<std::sync::Arc<super::grey_png::Grey>>,
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
        self.check().map_err(|e| e.at("grass.dynamics").into())
    }
}

impl Grass {
    pub fn check(&self) -> Check {
        if self.bunch.is_empty() && self.meadow.is_empty() && self.cover.is_none() {
            return Err(FieldError::new(
                "",
                "the scene has no grass; add a [[grass.bunch]], a [[grass.meadow]] or a [grass.cover]",
            ));
        }
        self.shape.check().map_err(|e| e.at("shape"))?;
        self.dynamics.check().map_err(|e| e.at("dynamics"))?;
        self.look.check().map_err(|e| e.at("look"))?;

        for (i, b) in self.bunch.iter().enumerate() {
            let at = format!("bunch[{i}]");
            finite(&format!("{at}.center"), &b.center)?;
            positive(&format!("{at}.radius"), b.radius, 10_000.0)?;
            in_range(&format!("{at}.count"), b.count, 1..=MAX_BLADES)?;
        }
        for (i, m) in self.meadow.iter().enumerate() {
            m.check().map_err(|e| e.at(&format!("meadow[{i}]")))?;
        }
        let total = self.blade_count();
        if total > MAX_BLADES {
            return Err(FieldError::new(
                "",
                format!("{total} blades in all is not allowed, use at most {MAX_BLADES}"),
            ));
        }
        if let Some(c) = &self.cover {
            c.check(MAX_BLADES - total).map_err(|e| e.at("cover"))?;
        }
        Ok(())
    }
}

impl BladeShape {
    /// The kinds' weights (at least one positive) and the height and
    /// width ranges.
    pub fn check(&self) -> Check {
        let weights = [self.upright, self.curved, self.drooping];
        for (name, w) in ["upright", "curved", "drooping"].into_iter().zip(weights) {
            if !(w.is_finite() && w >= 0.0) {
                return Err(FieldError::new(
                    name,
                    format!("{w} is not allowed, use a weight >= 0"),
                ));
            }
        }
        if weights.iter().sum::<f32>() <= 0.0 {
            return Err(FieldError::new(
                "",
                "the weights upright, curved and drooping are all zero; make one positive",
            ));
        }
        range_within("height", self.height, 0.01..=10.0)?;
        range_within("width", self.width, 0.0005..=1.0)?;
        Ok(())
    }
}

impl Meadow {
    /// Its place and size, one of count and density, and its mask's name.
    pub fn check(&self) -> Check {
        finite("center", &self.center)?;
        positive("size[0]", self.size[0], 10_000.0)?;
        positive("size[1]", self.size[1], 10_000.0)?;
        match (self.count, self.density) {
            (Some(n), None) => in_range("count", n, 1..=MAX_BLADES)?,
            (None, Some(d)) => {
                positive("density", d, 1e6)?;
                in_range("density", self.blades(), 1..=MAX_BLADES).map_err(
                    |_| {
                        FieldError::new(
                            "density",
                            format!(
                                "{d} per square metre gives {} blades, use a density giving 1..={MAX_BLADES}",
                                self.blades()
                            ),
                        )
                    },
                )?
            }
            (Some(_), Some(_)) => {
                return Err(FieldError::new(
                    "",
                    "has both count and density; give one of them",
                ))
            }
            (None, None) => {
                return Err(FieldError::new(
                    "",
                    "has neither count nor density; give one of them",
                ))
            }
        }
        if self
            .mask
            .as_ref()
            .is_some_and(|name| name.written.trim().is_empty())
        {
            return Err(FieldError::new(
                "mask",
                "is empty; name a grey PNG relative to the scene file",
            ));
        }
        Ok(())
    }
}

impl Look {
    /// `[grass.look]`'s values, each in its range.
    pub fn check(&self) -> Check {
        let unit = "a number from 0 to 1";
        within("hue", self.hue, 0.0..=1.0, unit)?;
        within("dryness", self.dryness, 0.0..=1.0, unit)?;
        within("tip", self.tip, 0.0..=1.0, unit)?;
        within(
            "clump_size",
            self.clump_size,
            0.0..=10.0,
            "metres from 0 (no clumps) to 10",
        )?;
        within("clump_variation", self.clump_variation, 0.0..=1.0, unit)?;
        within(
            "sheen",
            self.sheen,
            0.0..=4.0,
            "a number from 0 (none) to 4 (1: a leaf's)",
        )?;
        within(
            "translucency",
            self.translucency,
            0.0..=4.0,
            "a number from 0 (none) to 4 (1: a leaf's)",
        )
    }
}

impl Cover {
    /// The cover's values, and the blades it makes around the camera within
    /// the `room` the patches leave of `MAX_BLADES`.
    pub fn check(&self, room: usize) -> Check {
        positive("density", self.density(), 10_000.0)?;
        positive("view_distance", self.view_distance, VIEW_DISTANCE)?;
        within(
            "simulate_radius",
            self.simulate_radius(),
            0.0..=self.view_distance,
            &format!(
                "a distance in 0..={} m (the view distance)",
                self.view_distance
            ),
        )?;
        match (self.size, self.center) {
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
        let blades = super::cover::most_blades(self);
        if blades > room as u64 {
            let side = 2 * super::cover::tiles_reached(self.view_distance) + 1;
            return Err(FieldError::new(
                "view_distance",
                format!(
                    "{} m at {} blades a square metre makes {side} x {side} tiles of {} blades, {blades} blades ({:.1} GB of control points), over the {room} allowed; lower view_distance or density",
                    self.view_distance,
                    self.density(),
                    super::cover::per_tile(self.density()),
                    blades as f64 * 128.0 / 1e9
                ),
            ));
        }
        Ok(())
    }
}

impl GrassDynamics {
    pub fn check(&self) -> Check {
        for (name, range) in self.ranges() {
            range_within(name, range, f32::MIN..=f32::MAX)?;
        }
        for corner in self.corners() {
            blade_physics(&corner)?;
        }
        Ok(())
    }
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
