//! Criterion bench of the wind solver's CPU reference: one step on the
//! paper's 60 x 20 x 60 grid, with 30 Jacobi iterations and with the
//! default multigrid solve; and what a cover's wind window over terrain
//! does on the CPU at each move (steppe's: the moved grid voxelised, its
//! faces classified, the multigrid's hierarchy built). Run with
//! `cargo bench --bench wind_cpu`; results go in docs/perf.md.

use criterion::{criterion_group, criterion_main, Criterion};
use glam::{UVec3, Vec3};
use meadow::model::wind::{
    Classification, Gust, Inflow, PressureSolver, WindField, WindGrid, WindSettings, WindSource,
};

fn wind_step(c: &mut Criterion) {
    let grid = WindGrid::new(
        UVec3::new(60, 20, 60),
        Vec3::new(-6.0, 0.0, -6.0),
        Vec3::new(12.0, 3.0, 12.0),
    )
    .unwrap();
    let mut source = WindSource::fixed(Vec3::new(-2.0, 1.0, 0.0), Vec3::X, 20.0, 2.5);
    source.rotation_speed = 0.5;
    let settings = WindSettings {
        sources: vec![source],
        inflow: Some(Inflow {
            speed: 2.5,
            heading: 0.0,
            gust: Gust {
                amplitude: 0.5,
                frequency: 0.3,
                seed: 1,
            },
        }),
        obstacles: Vec::new(),
        solver: PressureSolver::Jacobi,
        jacobi_iterations: 30,
        ..Default::default()
    };
    let mut field = WindField::new(grid, &settings);
    // Start from a developed field, not from air at rest.
    for _ in 0..20 {
        field.step(&settings, 1.0 / 60.0);
    }
    let mut group = c.benchmark_group("wind CPU reference");
    group.sample_size(20);
    group.bench_function("step 60x20x60, 30 Jacobi", |b| {
        b.iter(|| field.step(&settings, 1.0 / 60.0))
    });
    let multigrid = WindSettings {
        solver: PressureSolver::Multigrid,
        ..settings.clone()
    };
    group.bench_function("step 60x20x60, multigrid", |b| {
        b.iter(|| field.step(&multigrid, 1.0 / 60.0))
    });
    group.finish();
}

fn window_move(c: &mut Criterion) {
    let scene = meadow::scene::Scene::builtin("steppe").unwrap();
    let grid = scene.wind_grid().unwrap();
    let settings = scene.wind_settings();
    let moved = grid.shifted(glam::IVec2::new(1, 0));
    let mut group = c.benchmark_group("wind window over terrain");
    group.sample_size(20);
    group.bench_function("steppe's move (40x24x40): Classification::of", |b| {
        b.iter(|| Classification::of(&moved, &settings))
    });
    group.finish();
}

criterion_group!(benches, wind_step, window_move);
criterion_main!(benches);
