//! Criterion bench of the grass dynamics' CPU reference: one step of 10,000
//! meadow blades, each sampling a developed wind field at its tip (as the
//! GPU kernel does). Reported as blades per second. Run with
//! `cargo bench --bench grass_cpu`; results go in docs/perf.md.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use meadow::model::wind::WindField;
use meadow::model::GrassField;
use meadow::scene::{field, Scene};

fn grass_step(c: &mut Criterion) {
    const BLADES: usize = 10_000;
    let mut scene = Scene::builtin("table1").unwrap();
    scene.set_blade_count(BLADES).unwrap();
    let blades = field::generate(&scene.grass, scene.seed).unwrap();
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed).unwrap();
    let settings = scene.wind_settings();
    let mut wind = WindField::new(scene.wind_grid().unwrap(), &settings);
    for _ in 0..30 {
        wind.step(&settings, scene.wind.dt);
    }
    let mut grass = GrassField::new(dynamic, scene.wind.dt).unwrap();
    let mut group = c.benchmark_group("grass CPU reference");
    group.sample_size(20);
    group.throughput(Throughput::Elements(BLADES as u64));
    group.bench_function(format!("step, {} substeps", grass.substeps), |b| {
        b.iter(|| grass.step(|x| wind.sample(x)))
    });
    group.finish();
}

criterion_group!(benches, grass_step);
criterion_main!(benches);
