//! Numerical stability: the strongest gusting, rotating wind the scene
//! format documents (tests/soak/storm.toml) blowing over a meadow for many
//! steps on the GPU, checked every few hundred steps (`SimRig::check`): no
//! NaN or infinite value in the wind field or the blades' state, no blade
//! below the ground by more than `GROUND_TOLERANCE`, roots fixed, and edge
//! lengths kept to `EDGE_TOLERANCE`.
//!
//! The suite runs a short version; `scripts/soak` runs the ignored
//! 100,000-step one in release mode and prints the figures that
//! docs/reliability.md records.

mod common;

use common::sim::{Figures, SimRig};
use common::{finish, strict_gpu};
use meadow::scene::Scene;

/// Relative change of any edge's length from rest (f32 rotations).
const EDGE_TOLERANCE: f32 = 1e-5;

fn storm(blades: usize) -> Scene {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/soak/storm.toml");
    let mut scene = Scene::load(path).unwrap_or_else(|e| panic!("{e}"));
    scene.set_blade_count(blades).unwrap();
    scene.validate().unwrap();
    scene
}

/// Runs `steps` wind + grass steps of the storm over `blades` blades,
/// checking the state every `check_every` steps; panics naming the first
/// broken invariant and the step it was seen at.
fn soak(blades: usize, steps: u64, check_every: u64) -> Figures {
    let scene = storm(blades);
    let gpu = strict_gpu();
    let mut rig = SimRig::new(&gpu, &scene);

    let mut figures = Figures::default();
    while rig.steps_done() < steps {
        rig.run(check_every.min(steps - rig.steps_done()));
        rig.check(&gpu, &mut figures);
        assert!(
            figures.worst_edge < EDGE_TOLERANCE,
            "step {}: an edge length changed by {:e} of its rest length",
            rig.steps_done(),
            figures.worst_edge
        );
    }
    // The share of blade-steps at an angle cap, printed for
    // docs/reliability.md. Not asserted yet: the storm is the strongest
    // wind the format documents, and the caps it reaches wait on issue 17
    // (swing by eq. 12, re-tuned scenes), after which the soak bounds it.
    let caps = rig.cap_counts(&gpu);
    eprintln!(
        "soak: {:.3}% of {} blade-steps at an angle cap ({:?})",
        100.0 * caps.fraction(),
        caps.blade_steps,
        caps
    );
    drop(rig);
    finish(gpu);
    eprintln!(
        "soak: {} steps over {} blades, {} checks: max wind {:.1} m/s, lowest point {:.4} m, worst edge length change {:.2e}, farthest tip {:.3} m, largest angle {:.3} rad",
        figures.steps,
        figures.blades,
        figures.checks,
        figures.max_wind,
        figures.lowest_point,
        figures.worst_edge,
        figures.farthest_tip,
        figures.largest_angle
    );
    figures
}

/// The short soak of the normal suite: a minute of simulated storm.
#[test]
fn a_minute_of_the_strongest_storm_keeps_the_meadow_finite_and_above_ground() {
    let f = soak(1000, 3600, 500);
    // The storm must actually bend the grass hard, or the soak proves nothing.
    assert!(
        f.farthest_tip > 0.2,
        "the storm barely moved the grass: {f:?}"
    );
    assert!(f.max_wind > 50.0, "the storm is not strong: {f:?}");
}

/// `scripts/soak`: 100,000 steps (27 minutes of simulated storm).
#[test]
#[ignore = "long: run by scripts/soak"]
fn soak_100k_steps_of_the_strongest_storm() {
    let steps = std::env::var("MEADOW_SOAK_STEPS")
        .ok()
        .map(|s| s.parse().expect("MEADOW_SOAK_STEPS is a step count"))
        .unwrap_or(100_000);
    let f = soak(4000, steps, 5000);
    assert!(
        f.farthest_tip > 0.2,
        "the storm barely moved the grass: {f:?}"
    );
}
