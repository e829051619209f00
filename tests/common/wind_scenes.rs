//! The wind scenes of the behaviour tests, shared by the CPU reference's
//! tests (tests/wind_cpu.rs) and the GPU solver's (tests/wind_gpu.rs), so
//! both are held to the same cases.

use glam::{UVec3, Vec3};
use meadow::model::wind::{Gust, Inflow, Obstacle, WindField, WindGrid, WindSettings, WindSource};

/// 24 x 10 x 24 cells over 12 x 5 x 12 m.
pub fn behaviour_grid() -> WindGrid {
    WindGrid::new(
        UVec3::new(24, 10, 24),
        Vec3::new(-6.0, 0.0, -6.0),
        Vec3::new(12.0, 5.0, 12.0),
    )
    .unwrap()
}

/// A source blowing along +x from the left half of the grid.
pub fn blowing_source() -> WindSource {
    WindSource::fixed(Vec3::new(-3.0, 1.5, 0.0), Vec3::X, 30.0, 2.5)
}

/// A 4 m/s inflow from the left against a wall across the middle.
pub fn wall_in_the_wind() -> WindSettings {
    WindSettings {
        inflow: Some(Inflow {
            speed: 4.0,
            heading: 0.0,
            gust: Gust::default(),
        }),
        obstacles: vec![Obstacle::Box {
            min: Vec3::new(-1.0, 0.0, -1.5),
            max: Vec3::new(0.0, 3.0, 1.5),
        }],
        jacobi_iterations: 40,
        ..Default::default()
    }
}

/// Mean wind speed 1 m up in the wall's lee and beside it.
pub fn lee_and_beside(sample: impl Fn(Vec3) -> Vec3) -> (f32, f32) {
    let speed = |x: f32, z: f32| sample(Vec3::new(x, 1.0, z)).length();
    let lee = (speed(1.0, 0.0) + speed(1.5, 0.0)) / 2.0;
    let beside = (speed(1.0, 4.0) + speed(1.5, 4.0) + speed(1.0, -4.0) + speed(1.5, -4.0)) / 4.0;
    (lee, beside)
}

/// A source in the centre turning a quarter turn per second.
pub fn rotating_source() -> WindSettings {
    let mut source = WindSource::fixed(Vec3::new(0.0, 1.5, 0.0), Vec3::X, 20.0, 4.0);
    source.rotation_speed = std::f32::consts::FRAC_PI_2;
    WindSettings {
        sources: vec![source],
        jacobi_iterations: 30,
        ..Default::default()
    }
}

/// `blowing_source` switched off after 1 s.
pub fn switched_off_after_one_second() -> WindSettings {
    let mut source = blowing_source();
    source.off_after = Some(1.0);
    WindSettings {
        sources: vec![source],
        jacobi_iterations: 30,
        ..Default::default()
    }
}

/// Sum of squared face velocities.
pub fn kinetic_energy(vel: &[Vec<f32>; 3]) -> f64 {
    vel.iter().flatten().map(|&v| (v as f64).powi(2)).sum()
}

/// Where a correlation sampled at separations 0, `spacing`, 2 `spacing`,
/// ... peaks between its samples: the parabola through its largest inner
/// sample and their neighbours (the moving frame's ridge at one lag).
pub fn ridge(rho: &[f64], spacing: f64) -> f64 {
    let m = (1..rho.len() - 1)
        .max_by(|&a, &b| rho[a].total_cmp(&rho[b]))
        .unwrap();
    let curve = rho[m - 1] - 2.0 * rho[m] + rho[m + 1];
    spacing * (m as f64 + 0.5 * (rho[m - 1] - rho[m + 1]) / curve)
}

/// The downwind wind at `points`, steps of `dt` from rest, sampled every
/// third step for `seconds` after the first `skip_s` seconds (20 samples a
/// second at 1/60 s, against 1.4 Hz at most): [point][sample].
pub fn downwind_wind(
    grid: WindGrid,
    settings: &WindSettings,
    dt: f32,
    skip_s: f32,
    seconds: f32,
    points: &[Vec3],
) -> Vec<Vec<f64>> {
    let mut field = WindField::new(grid, settings);
    let skip = (skip_s / dt).round() as u32;
    let steps = skip + (seconds / dt).round() as u32;
    let mut series = vec![Vec::new(); points.len()];
    for step in 0..steps {
        field.step(settings, dt);
        if step >= skip && (step - skip) % 3 == 2 {
            for (s, p) in series.iter_mut().zip(points) {
                s.push(field.sample(*p).x as f64);
            }
        }
    }
    series
}
