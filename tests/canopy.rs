//! Two-way coupling (src/model/canopy.rs): the grass slows the wind. The GPU
//! against the CPU reference, and the behaviour a canopy shows: slower air
//! below the blades' height than above it, with the profile's attenuation
//! fitted; one-way (the paper's) the profile stays flat.

use crate::common;

use common::sim::SimRig;
use common::{finish, strict_gpu};
use meadow::model::canopy;
use meadow::model::wind::WindField;
use meadow::model::GrassField;
use meadow::scene::file::parse;
use meadow::scene::{field, Scene};

/// A dense meadow `size` metres in a steady wind from the left.
fn meadow(coupling: &str, size: [f32; 2], density: f32, cells: [u32; 3], gust: f32) -> Scene {
    parse(
        &format!(
            r#"
name = "canopy-test"
seed = 7
[camera]
position = [0.0, 2.0, 8.0]
target = [0.0, 0.0, 0.0]
fov_y = 50.0
[[grass.meadow]]
center = [0.0, 0.0]
size = [{}, {}]
density = {density}
[wind]
cells = [{}, {}, {}]
height = 3.0
coupling = "{coupling}"
[wind.inflow]
speed = 3.0
gust = {{ amplitude = {gust}, frequency = 0.5, seed = 3 }}
"#,
            size[0], size[1], cells[0], cells[1], cells[2]
        ),
        "canopy test scene",
    )
    .unwrap()
}

#[test]
fn gpu_and_cpu_agree_with_two_way_coupling() {
    let scene = meadow("two-way", [3.0, 3.0], 300.0, [18, 12, 18], 0.5);
    let steps = 120;
    let settings = scene.wind_settings();
    let grid = scene.wind_grid().unwrap();
    let rest = scene.field().unwrap();
    let blades = field::dynamic_blades(&rest, &scene.grass.dynamics, scene.seed).unwrap();

    // CPU reference, and the same steps one-way to see the coupling matter.
    let mut wind = WindField::new(grid, &settings);
    wind.canopy_unit = canopy::unit(&blades);
    let mut grass = GrassField::new(blades.clone(), scene.wind.dt).unwrap();
    for _ in 0..steps {
        canopy::coupled_step(&mut wind, &settings, &mut grass);
    }
    let mut one_way = meadow("one-way", [3.0, 3.0], 300.0, [18, 12, 18], 0.5);
    one_way.seed = scene.seed;
    let one_way_settings = one_way.wind_settings();
    let mut free = WindField::new(grid, &one_way_settings);
    let mut free_grass = GrassField::new(blades.clone(), scene.wind.dt).unwrap();
    for _ in 0..steps {
        canopy::coupled_step(&mut free, &one_way_settings, &mut free_grass);
    }
    assert!(
        free.canopy.iter().all(|&c| c == 0),
        "one-way grass laid area"
    );

    let gpu = strict_gpu();
    let mut rig = SimRig::new(&gpu, &scene);
    rig.run(steps);
    let vel = rig.velocity(&gpu);
    let counts = rig.canopy(&gpu);
    let states = rig.states(&gpu);
    drop(rig);
    finish(gpu);

    let l2 = |a: &[Vec<f32>; 3], b: &[Vec<f32>; 3]| {
        let (mut diff, mut norm) = (0.0f64, 0.0f64);
        for (x, y) in a.iter().flatten().zip(b.iter().flatten()) {
            diff += ((x - y) as f64).powi(2);
            norm += (*y as f64).powi(2);
        }
        (diff / norm).sqrt()
    };
    let velocity = l2(&vel, &wind.vel);
    let coupling = l2(&free.vel, &wind.vel);
    let total = |c: &[u32]| c.iter().map(|&c| c as f64).sum::<f64>();
    let area = (total(&counts) - total(&wind.canopy)).abs() / total(&wind.canopy);
    let cell_diff = counts
        .iter()
        .zip(&wind.canopy)
        .map(|(&g, &c)| g.abs_diff(c) as f64 / (c as f64).max(1.0))
        .fold(0.0, f64::max);
    let angle = states
        .iter()
        .zip(&grass.states)
        .flat_map(|(g, c)| (0..4).map(move |m| (g.angle[m] - c.angle[m]).abs()))
        .fold(0.0f32, f32::max);
    eprintln!(
        "after {steps} coupled steps: wind relative L2 GPU vs CPU {velocity:e} (coupled vs \
         one-way {coupling:e}); canopy area {area:e} of the total, worst cell {cell_diff:e}; \
         angles {angle:e} rad; total area {:.3} m^2",
        total(&wind.canopy) * wind.canopy_unit as f64
    );
    assert!(
        coupling > 0.02,
        "the coupling barely changed the wind ({coupling:e}): nothing to compare"
    );
    // Measured on lavapipe: 4.5e-7, 9.2e-10 (worst cell 6.2e-6) and
    // 8.9e-7 rad; the bounds are ten to twenty times that. The area sums
    // in whole counts: a count can round apart on the two sides.
    assert!(
        velocity < 1e-5,
        "wind differs by {velocity:e} (relative L2)"
    );
    assert!(area < 1e-6 && cell_diff < 1e-4, "canopy area differs");
    assert!(angle < 1e-5, "blade angles differ by {angle:e} rad");
}

/// The wind profile over the meadow's downwind part: per layer of cells,
/// the mean along-wind speed and the mean frontal area (m^2 per cell).
struct Profile {
    height: Vec<f32>,
    speed: Vec<f32>,
    area: Vec<f64>,
}

fn profile(scene: &Scene, seconds: u64) -> Profile {
    let grid = scene.wind_grid().unwrap();
    let gpu = strict_gpu();
    let mut rig = SimRig::new(&gpu, scene);
    rig.run(60 * seconds);
    let vel = rig.velocity(&gpu);
    let counts = rig.canopy(&gpu);
    drop(rig);
    finish(gpu);
    let unit = canopy::unit(
        &field::dynamic_blades(&scene.field().unwrap(), &scene.grass.dynamics, scene.seed).unwrap(),
    ) as f64;
    let ([x0, z0], [x1, z1]) = scene.grass_bounds();
    let n = grid.cells;
    let mut out = Profile {
        height: Vec::new(),
        speed: Vec::new(),
        area: Vec::new(),
    };
    for j in 0..n.y {
        let (mut speed, mut area, mut cells) = (0.0f64, 0.0f64, 0);
        for k in 0..n.z {
            for i in 0..n.x {
                let c = grid.cell_center(i, j, k);
                // The downwind two thirds of the field, away from its sides.
                let inside =
                    c.x > x0 + (x1 - x0) / 3.0 && c.x < x1 && c.z > z0 + 1.0 && c.z < z1 - 1.0;
                if inside {
                    let u = vel[0][grid.face_index(0, i, j, k)]
                        + vel[0][grid.face_index(0, i + 1, j, k)];
                    speed += 0.5 * u as f64;
                    area += counts[grid.cell_index(i, j, k)] as f64 * unit;
                    cells += 1;
                }
            }
        }
        out.height.push(grid.cell_center(0, j, 0).y);
        out.speed.push((speed / cells as f64) as f32);
        out.area.push(area / cells as f64);
    }
    out
}

impl Profile {
    /// The canopy's height h: the top of the highest layer holding at
    /// least a tenth of the densest layer's frontal area.
    fn canopy_height(&self, cell: f32) -> f32 {
        let densest = self.area.iter().cloned().fold(0.0, f64::max);
        let top = (0..self.area.len())
            .rev()
            .find(|&j| self.area[j] >= 0.1 * densest)
            .unwrap_or(0);
        self.height[top] + 0.5 * cell
    }

    /// The speed at height z, linear between layer centres.
    fn speed_at(&self, z: f32) -> f32 {
        let j = self
            .height
            .iter()
            .position(|&y| y > z)
            .unwrap_or(self.height.len() - 1)
            .max(1);
        let f = (z - self.height[j - 1]) / (self.height[j] - self.height[j - 1]);
        self.speed[j - 1] * (1.0 - f) + self.speed[j] * f
    }

    /// alpha of u(z) / u(h) = exp(alpha (z / h - 1)), least squares on
    /// the layers below h (through the origin: the fit passes u(h)).
    fn attenuation(&self, h: f32) -> f32 {
        let u_h = self.speed_at(h);
        let (mut xy, mut xx) = (0.0f32, 0.0f32);
        for (&z, &u) in self.height.iter().zip(&self.speed) {
            if z < h && u > 0.0 {
                let x = z / h - 1.0;
                xy += x * (u / u_h).ln();
                xx += x * x;
            }
        }
        xy / xx
    }

    /// Mean speed of the layers below h, and of those between h and 2h.
    fn below_and_above(&self, h: f32) -> (f32, f32) {
        let mean = |keep: &dyn Fn(f32) -> bool| {
            let v: Vec<f32> = self
                .height
                .iter()
                .zip(&self.speed)
                .filter(|(&z, _)| keep(z))
                .map(|(_, &u)| u)
                .collect();
            v.iter().sum::<f32>() / v.len() as f32
        };
        (mean(&|z| z < h), mean(&|z| z > h && z < 2.0 * h))
    }
}

/// Over a dense meadow (300 blades per square metre, 12 x 4 m) in a steady
/// 3 m/s wind, after 5 s: two-way, the air below the blades' height is
/// slower than above it and the profile falls into the canopy as
/// u(z) / u(h) = exp(alpha (z / h - 1)) with alpha as field canopies show
/// (about 1 to 3); one-way, it is flat.
#[test]
fn the_grass_slows_the_air_below_its_height() {
    let cells = [40, 20, 12];
    let cell = 3.0 / cells[1] as f32;
    let two_way = profile(&meadow("two-way", [12.0, 4.0], 300.0, cells, 0.0), 5);
    let h = two_way.canopy_height(cell);
    let alpha = two_way.attenuation(h);
    let (below, above) = two_way.below_and_above(h);
    let one_way = profile(&meadow("one-way", [12.0, 4.0], 300.0, cells, 0.0), 5);
    let flat_alpha = one_way.attenuation(h);
    let (flat_below, flat_above) = one_way.below_and_above(h);
    for j in 0..two_way.height.len() {
        eprintln!(
            "z {:.3} m: two-way {:.3} m/s (area {:.4} m^2 per cell), one-way {:.3} m/s",
            two_way.height[j], two_way.speed[j], two_way.area[j], one_way.speed[j]
        );
    }
    eprintln!(
        "canopy height {h:.3} m; two-way: alpha {alpha:.2}, mean below h {below:.3} m/s, \
         between h and 2h {above:.3} m/s; one-way: alpha {flat_alpha:.3}, {flat_below:.3} \
         and {flat_above:.3} m/s"
    );
    assert!(
        below < 0.6 * above,
        "two-way: the air below the blades ({below} m/s) is not slower than above ({above} m/s)"
    );
    assert!(
        (1.0..=3.0).contains(&alpha),
        "two-way: attenuation alpha {alpha} outside field canopies' 1..3"
    );
    assert!(
        (flat_below / flat_above - 1.0).abs() < 0.02 && flat_alpha.abs() < 0.05,
        "one-way: the profile is not flat (alpha {flat_alpha}, {flat_below} vs {flat_above} m/s)"
    );
}
