//! Scenes: what grass grows where, the camera, the light and the level of
//! detail. Built-in scenes live here; scene files (TOML) use the same types.

pub mod field;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::sim::wind::{
    Gust, Inflow, Obstacle, WindGrid, WindSettings, WindSource, DEFAULT_JACOBI_ITERATIONS,
};
use crate::sim::BladePhysics;

/// A region of grass.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase", deny_unknown_fields)]
pub enum GrassPatch {
    /// A tuft of `count` blades within `radius` of `center` (world x, z).
    Bunch {
        center: [f32; 2],
        radius: f32,
        count: usize,
    },
    /// `count` blades spread over a `size` (x, z) rectangle around `center`.
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

    fn set_count(&mut self, n: usize) {
        match self {
            GrassPatch::Bunch { count, .. } | GrassPatch::Meadow { count, .. } => *count = n,
        }
    }
}

/// How blade shapes are drawn: the mix of kinds (relative weights) and the
/// ranges of height and full width, in metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
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

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    pub position: [f32; 3],
    pub target: [f32; 3],
    /// Vertical field of view in degrees.
    pub fov_y: f32,
}

/// A directional light (the sun).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Light {
    /// Direction toward the light (normalised on use).
    pub direction: [f32; 3],
    pub color: [f32; 3],
    pub ambient: f32,
}

/// Level of detail (paper section 5.1): tessellation level by distance.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lod {
    pub enabled: bool,
    /// Closer than this: the close level.
    pub close_distance: f32,
    /// Closer than this (and not close): the medium level; beyond: far.
    pub far_distance: f32,
    /// Segments per blade for close, medium, far: the paper's 20, 10, 3.
    pub levels: [u32; 3],
}

impl Default for Lod {
    fn default() -> Self {
        Self {
            enabled: true,
            close_distance: 4.0,
            far_distance: 9.0,
            levels: [20, 10, 3],
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    pub name: String,
    pub seed: u64,
    pub grass: Vec<GrassPatch>,
    pub shape: BladeShape,
    pub camera: Camera,
    pub light: Light,
    pub lod: Lod,
    /// Half the side of the ground square, centred under the grass.
    pub ground_half_extent: f32,
    pub wind: WindConfig,
    /// The blades' physical parameters (method.md section 4).
    #[serde(default)]
    pub dynamics: GrassDynamics,
}

/// The grass's physical parameters, which the paper does not give (ours):
/// every blade draws each one uniformly from its [min, max] range, seeded,
/// so that no two blades sway in step. Defaults give a bending frequency of
/// about 1-2 Hz and a tip-edge deflection of about 0.3 rad in a 2.5 m/s wind
/// for the default blade shapes (docs/architecture.md, "Grass dynamics").
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
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
    /// The corners of the ranges as blade parameters.
    fn corners(&self) -> [BladePhysics; 2] {
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
        for (name, [lo, hi]) in [
            ("edge_mass", self.edge_mass),
            ("sigma", self.sigma),
            ("tip_stiffness", self.tip_stiffness),
            ("stiffness_ratio", self.stiffness_ratio),
            ("damping_ratio", self.damping_ratio),
        ] {
            if lo > hi {
                return Err(Error::InvalidInput(format!(
                    "grass dynamics: {name} range [{lo}, {hi}] is reversed, write [min, max]"
                )));
            }
        }
        for corner in self.corners() {
            corner.validate()?;
        }
        Ok(())
    }
}

/// The wind of a scene (method.md section 3): the grid spans the grass's
/// bounding box plus a margin, from the ground up to `height`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WindConfig {
    /// Cells along x, y (up), z: the paper's grid is 60 x 20 x 60.
    pub cells: [u32; 3],
    /// Height of the air the grid covers (m).
    pub height: f32,
    /// Horizontal margin around the grass (m).
    pub margin: f32,
    /// Jacobi iterations of the pressure solve per step.
    pub jacobi_iterations: u32,
    /// Simulation step (s); the frame rate never changes it.
    pub dt: f32,
    pub sources: Vec<WindSource>,
    pub inflow: Option<Inflow>,
    pub obstacles: Vec<Obstacle>,
}

impl WindConfig {
    /// Wind from the left (paper Fig. 10): a gusting inflow along +x.
    pub fn from_the_left(speed: f32) -> Self {
        Self {
            cells: [60, 20, 60],
            height: 3.0,
            margin: 1.5,
            jacobi_iterations: DEFAULT_JACOBI_ITERATIONS,
            dt: 1.0 / 60.0,
            sources: Vec::new(),
            inflow: Some(Inflow {
                speed,
                gust: Gust {
                    amplitude: 0.5,
                    frequency: 0.3,
                    seed: 1,
                },
            }),
            obstacles: Vec::new(),
        }
    }

    pub fn settings(&self) -> WindSettings {
        WindSettings {
            sources: self.sources.clone(),
            inflow: self.inflow,
            obstacles: self.obstacles.clone(),
            jacobi_iterations: self.jacobi_iterations,
        }
    }
}

/// Names of the built-in scenes.
pub const BUILTIN: &[&str] = &["few-bunches", "several-bunches", "meadow"];

/// The most blades one scene may hold: beyond this the blade buffer alone
/// passes 1 GiB, and lavapipe would take hours per frame.
pub const MAX_BLADES: usize = 10_000_000;

fn sun() -> Light {
    Light {
        direction: [0.45, 0.75, 0.35],
        color: [1.0, 0.96, 0.86],
        ambient: 0.28,
    }
}

impl Scene {
    /// A built-in scene by name.
    pub fn builtin(name: &str) -> Result<Scene> {
        let scene = match name {
            // Paper Fig. 10 (left): a few bunches, seen from close by.
            "few-bunches" => Scene {
                name: name.into(),
                seed: 1,
                grass: [[-0.55, 0.1], [0.0, -0.25], [0.55, 0.15]]
                    .into_iter()
                    .map(|c| GrassPatch::Bunch {
                        center: c,
                        radius: 0.12,
                        count: 70,
                    })
                    .collect(),
                shape: BladeShape::default(),
                camera: Camera {
                    position: [0.0, 0.75, 2.3],
                    target: [0.0, 0.3, 0.0],
                    fov_y: 40.0,
                },
                light: sun(),
                lod: Lod::default(),
                ground_half_extent: 6.0,
                wind: WindConfig::from_the_left(2.5),
                dynamics: GrassDynamics::default(),
            },
            // Paper Fig. 10 (right): several bunches on a 3 x 3 layout.
            "several-bunches" => Scene {
                name: name.into(),
                seed: 2,
                grass: (0..9)
                    .map(|i| GrassPatch::Bunch {
                        center: [((i % 3) as f32 - 1.0) * 0.9, ((i / 3) as f32 - 1.0) * 0.9],
                        radius: 0.14,
                        count: 70,
                    })
                    .collect(),
                shape: BladeShape::default(),
                camera: Camera {
                    position: [0.0, 1.4, 3.4],
                    target: [0.0, 0.2, 0.0],
                    fov_y: 45.0,
                },
                light: sun(),
                lod: Lod::default(),
                ground_half_extent: 8.0,
                wind: WindConfig::from_the_left(2.5),
                dynamics: GrassDynamics::default(),
            },
            // A meadow seen from standing height, reaching to the medium and
            // far levels of detail.
            "meadow" => Scene {
                name: name.into(),
                seed: 3,
                grass: vec![GrassPatch::Meadow {
                    center: [0.0, 0.0],
                    size: [30.0, 30.0],
                    count: 200_000,
                }],
                shape: BladeShape::default(),
                camera: Camera {
                    position: [0.0, 1.5, 7.5],
                    target: [0.0, 0.2, 0.0],
                    fov_y: 50.0,
                },
                light: sun(),
                lod: Lod::default(),
                ground_half_extent: 40.0,
                wind: WindConfig::from_the_left(3.0),
                dynamics: GrassDynamics::default(),
            },
            other => {
                return Err(Error::InvalidInput(format!(
                    "unknown scene {other:?}; the built-in scenes are: {}",
                    BUILTIN.join(", ")
                )))
            }
        };
        Ok(scene)
    }

    pub fn blade_count(&self) -> usize {
        self.grass.iter().map(GrassPatch::count).sum()
    }

    /// Sets the total blade count, shared among the patches in proportion
    /// to their current counts (the remainder goes to the first patches).
    pub fn set_blade_count(&mut self, total: usize) -> Result<()> {
        if total == 0 || total > MAX_BLADES {
            return Err(Error::InvalidInput(format!(
                "--blades {total} is not allowed, use 1..={MAX_BLADES}"
            )));
        }
        let old = self.blade_count().max(1);
        let mut counts: Vec<usize> = self.grass.iter().map(|p| p.count() * total / old).collect();
        // Each share is rounded down by less than one, so fewer than
        // `counts.len()` blades are left over.
        let left = total - counts.iter().sum::<usize>();
        for c in counts.iter_mut().take(left) {
            *c += 1;
        }
        for (p, c) in self.grass.iter_mut().zip(counts) {
            p.set_count(c);
        }
        Ok(())
    }

    /// Bounding box (x, z) of where the grass grows: (min, max).
    pub fn grass_bounds(&self) -> ([f32; 2], [f32; 2]) {
        let mut lo = [f32::MAX; 2];
        let mut hi = [f32::MIN; 2];
        for p in &self.grass {
            let (c, half) = match *p {
                GrassPatch::Bunch { center, radius, .. } => (center, [radius, radius]),
                GrassPatch::Meadow { center, size, .. } => (center, [size[0] / 2.0, size[1] / 2.0]),
            };
            for a in 0..2 {
                lo[a] = lo[a].min(c[a] - half[a]);
                hi[a] = hi[a].max(c[a] + half[a]);
            }
        }
        (lo, hi)
    }

    /// The wind grid: the grass's bounding box plus the margin, ground to `height`.
    pub fn wind_grid(&self) -> Result<WindGrid> {
        let w = &self.wind;
        let (lo, hi) = self.grass_bounds();
        let origin = Vec3::new(lo[0] - w.margin, 0.0, lo[1] - w.margin);
        let size = Vec3::new(
            hi[0] - lo[0] + 2.0 * w.margin,
            w.height,
            hi[1] - lo[1] + 2.0 * w.margin,
        );
        if !(w.dt.is_finite() && w.dt > 0.0 && w.dt <= 0.1) {
            return Err(Error::InvalidInput(format!(
                "wind.dt {} is not allowed, use 0 < dt <= 0.1 s",
                w.dt
            )));
        }
        if w.jacobi_iterations > 10_000 {
            return Err(Error::InvalidInput(format!(
                "wind.jacobi_iterations {} is not allowed, use 0..=10000",
                w.jacobi_iterations
            )));
        }
        WindGrid::new(glam::UVec3::from(w.cells), origin, size)
    }

    /// Centre of the grass (x, z), for the ground square.
    pub fn grass_center(&self) -> Vec3 {
        let n = self.grass.len().max(1) as f32;
        let sum = self.grass.iter().fold(Vec3::ZERO, |acc, p| {
            let c = match p {
                GrassPatch::Bunch { center, .. } | GrassPatch::Meadow { center, .. } => *center,
            };
            acc + Vec3::new(c[0], 0.0, c[1])
        });
        sum / n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blade_count_is_shared_exactly() {
        let mut s = Scene::builtin("several-bunches").unwrap();
        for total in [1, 8, 9, 10, 1000, 12345] {
            s.set_blade_count(total).unwrap();
            assert_eq!(s.blade_count(), total);
        }
        assert!(s.set_blade_count(0).is_err());
        assert!(s.set_blade_count(MAX_BLADES + 1).is_err());
    }

    #[test]
    fn unknown_scene_names_the_choices() {
        let e = Scene::builtin("nope").unwrap_err().to_string();
        assert!(e.contains("unknown scene") && e.contains("meadow"), "{e}");
    }
}
