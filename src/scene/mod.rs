//! Scenes: what grass grows where, the wind, the camera, the light, the
//! level of detail and the render settings. A scene is a TOML file
//! (docs/scenes.md); the built-in scenes are the files under `scenes/`,
//! compiled in, so a user can copy one and edit it.
//!
//! This file holds the `Scene` and what it derives (its blades, bounds,
//! wind grid). Its children:
//! - `view.rs`, `grass.rs`, `wind.rs`, `ground.rs`: the file's sections,
//!   each type beside its check;
//! - `check.rs`: the checks' helpers and limits, and the checks that need
//!   the whole scene (the camera above the ground and reaching the grass);
//! - `file.rs`: reading a file, its errors at a line and column;
//! - `field.rs`: planting the blades; `cover/`: the endless cover;
//!   `grey_png.rs`: the grey PNGs of masks and height maps.

pub mod check;
pub mod cover;
pub mod field;
pub mod file;
mod grass;
pub mod grey_png;
mod ground;
mod view;
mod wind;

pub use grass::*;
pub use ground::{Ground, SceneFiles};
pub use view::*;
pub use wind::*;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::model::collider::Collider;
use crate::model::terrain::Terrain;
use crate::model::wind::{PressureSolver, WindGrid, WindSettings};

/// The most blades one scene may hold: beyond this the blade buffer alone
/// passes 1 GiB, and lavapipe would take hours per frame.
pub const MAX_BLADES: usize = 10_000_000;

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
        wind.check()
            .map_err(|e| bad(format!("({}) {}", e.path, e.message)))?;
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
        w.check().map_err(|e| e.at("wind"))?;
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
