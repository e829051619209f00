//! Numerical stability: the strongest gusting, rotating wind the scene
//! format documents (tests/soak/storm.toml) blowing over a meadow for many
//! steps on the GPU, checked every few hundred steps: no NaN or infinite
//! value in the wind field or the blades' state, no blade below the ground
//! by more than `GROUND_TOLERANCE`, roots fixed and edge lengths kept.
//!
//! The suite runs a short version; `scripts/soak` runs the ignored
//! 100,000-step one in release mode and prints the figures that
//! docs/reliability.md records.

mod common;

use common::sim::SimRig;
use common::{finish, strict_gpu, to_vec3};
use glam::Vec3;
use meadow::scene::Scene;

/// How far below the ground plane (y = 0) any control point may go, in
/// metres. The curve lies in its control points' convex hull, so this
/// bounds the drawn blade too.
const GROUND_TOLERANCE: f32 = 0.01;

/// Relative change of any edge's length from rest (f32 rotations).
const EDGE_TOLERANCE: f32 = 1e-5;

#[derive(Debug, Default)]
struct Figures {
    steps: u64,
    blades: usize,
    checks: u32,
    /// The fastest wind anywhere in the grid at any check (m/s).
    max_wind: f32,
    /// The lowest control point at any check (m; negative is below ground).
    lowest_point: f32,
    /// The largest relative edge-length change at any check.
    worst_edge: f32,
    /// The farthest any tip got from its rest place (m).
    farthest_tip: f32,
    /// The largest angle of any motion at any check (rad).
    largest_angle: f32,
}

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

    let mut figures = Figures {
        blades: rig.blades.len(),
        lowest_point: f32::INFINITY,
        ..Default::default()
    };
    while rig.steps_done() < steps {
        rig.run(&gpu, check_every.min(steps - rig.steps_done()));
        let done = rig.steps_done();
        figures.checks += 1;
        let velocity = rig.velocity(&gpu);
        for (axis, v) in velocity.iter().enumerate() {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                panic!("step {done}: wind component {axis} at face {i} is {}", v[i]);
            }
            let fastest = v.iter().fold(0.0f32, |m, x| m.max(x.abs()));
            figures.max_wind = figures.max_wind.max(fastest);
        }
        let states = rig.states(&gpu);
        let out = rig.vertices(&gpu);
        for (i, blade) in rig.blades.iter().enumerate() {
            let s = &states[i];
            assert!(
                s.angle.iter().chain(&s.velocity).all(|x| x.is_finite()),
                "step {done}: blade {i} state {s:?}"
            );
            figures.largest_angle = s
                .angle
                .iter()
                .fold(figures.largest_angle, |m, a| m.max(a.abs()));
            let v = &out[4 * i..4 * i + 4];
            assert!(
                v.iter()
                    .all(|v| v.position.iter().chain(&v.width).all(|x| x.is_finite())),
                "step {done}: blade {i} vertices {v:?}"
            );
            let p: Vec<Vec3> = v.iter().map(|v| to_vec3(v.position)).collect();
            assert_eq!(
                p[0],
                blade.rest_point(0),
                "step {done}: blade {i} root moved"
            );
            for e in 0..3 {
                let rest = blade.rest_point(e + 1).distance(blade.rest_point(e));
                let error = (p[e + 1].distance(p[e]) - rest).abs() / rest;
                figures.worst_edge = figures.worst_edge.max(error);
            }
            let lowest = p.iter().map(|p| p.y).fold(f32::INFINITY, f32::min);
            figures.lowest_point = figures.lowest_point.min(lowest);
            assert!(
                lowest >= -GROUND_TOLERANCE,
                "step {done}: blade {i} reaches {lowest} m below the ground (tolerance {GROUND_TOLERANCE} m): {p:?}"
            );
            figures.farthest_tip = figures.farthest_tip.max(p[3].distance(blade.rest_point(3)));
        }
        assert!(
            figures.worst_edge < EDGE_TOLERANCE,
            "step {done}: an edge length changed by {:e} of its rest length",
            figures.worst_edge
        );
    }
    figures.steps = rig.steps_done();
    rig.destroy(&gpu);
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
