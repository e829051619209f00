//! Touch, the CPU reference (src/model/contact.rs): a ball moving through a
//! strip of meadow presses the blades it touches out of its way and they
//! rise again; a ball laid on the meadow leaves no blade inside it.

use glam::Vec3;
use meadow::model::contact::{Collider, ColliderKind, ColliderState};
use meadow::model::GrassField;
use meadow::scene::{field, Scene};

const RADIUS: f32 = 0.4;
/// How far a point of a blade may lie inside a ball moving at 1.2 m/s
/// (docs/physics.md): about the 2 cm it travels in a step; blades it rolls
/// over lie nearly flat under it.
const MOVING_TOLERANCE: f32 = 0.025;
/// ... and inside a resting ball, once the contact has settled.
const RESTING_TOLERANCE: f32 = 0.006;

/// The roll scene's meadow cut to a 3 x 1 m strip of `count` blades.
fn strip(count: usize) -> (Scene, GrassField) {
    let mut scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/roll.toml")).unwrap();
    scene.grass.meadow[0].size = [3.0, 1.0];
    scene.set_blade_count(count).unwrap();
    let blades = field::generate(&scene.grass, scene.seed).unwrap();
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed).unwrap();
    let grass = GrassField::new(dynamic, scene.wind.dt).unwrap();
    (scene, grass)
}

fn ball(path: Vec<Vec3>, speed: f32) -> Collider {
    Collider {
        kind: ColliderKind::Sphere,
        radius: RADIUS,
        height: 0.0,
        position: path[0],
        path,
        path_speed: speed,
        closed: false,
        roll: false,
        ..Default::default()
    }
}

/// The deepest any point of the drawn curve (64 samples) or any control
/// point of any blade lies inside `c` (0: none inside).
fn deepest_inside(grass: &GrassField, c: &ColliderState) -> (f32, f32) {
    let mut curve = 0.0f32;
    let mut control = 0.0f32;
    for p in grass.poses() {
        for q in &p.points[1..] {
            control = control.max(-c.distance(*q).0);
        }
        for k in 1..=64 {
            let u = k as f32 / 64.0;
            let v = 1.0 - u;
            let q = p.points[0] * (v * v * v)
                + p.points[1] * (3.0 * v * v * u)
                + p.points[2] * (3.0 * v * u * u)
                + p.points[3] * (u * u * u);
            curve = curve.max(-c.distance(q).0);
        }
    }
    (control, curve)
}

fn tip_heights(grass: &GrassField) -> Vec<f32> {
    grass.poses().map(|p| p.points[3].y).collect()
}

#[test]
fn a_ball_through_a_strip_lowers_the_tips_it_touches_and_they_rise_again() {
    let (_, grass) = strip(1500);
    let from = Vec3::new(-2.2, RADIUS, 0.0);
    // Far enough past the strip's end (1.5 m) that no blade reaches it.
    let to = Vec3::new(3.0, RADIUS, 0.0);
    let speed = 1.2;
    let mut grass = grass.with_colliders(vec![ball(vec![from, to], speed)]);
    let rest = tip_heights(&grass);
    let dt = grass.dt;
    let steps_across = ((to.x - from.x) / speed / dt).ceil() as usize;
    let mut touched = vec![false; rest.len()];
    let mut worst = (0.0f32, 0.0f32);
    let mut lowest = 0.0f32;
    let mut lowered = Vec::new();
    for step in 0..steps_across {
        let before = grass.pressed.clone();
        grass.step(|_| Vec3::ZERO);
        // Touched in this step: the pressed state rose (or stayed full).
        let now_touched: Vec<bool> = grass
            .pressed
            .iter()
            .zip(&before)
            .map(|(p, _)| p.touched != 0.0)
            .collect();
        let now = grass.colliders[0].at(meadow::model::contact::step_end_time(step as u64, dt));
        let (control, curve) = deepest_inside(&grass, &now);
        worst = (worst.0.max(control), worst.1.max(curve));
        lowest = grass
            .poses()
            .flat_map(|p| p.points)
            .map(|q| q.y)
            .fold(lowest, f32::min);
        for (t, &now) in touched.iter_mut().zip(&now_touched) {
            *t |= now;
        }
        // Half way: the blades touched in this step, their tips against rest.
        if step == steps_across / 2 {
            let tips = tip_heights(&grass);
            for (i, &now) in now_touched.iter().enumerate() {
                if now {
                    lowered.push(tips[i] / rest[i]);
                }
            }
        }
    }
    let n_touched = touched.iter().filter(|&&t| t).count();
    let mean_lowered = lowered.iter().sum::<f32>() / lowered.len() as f32;
    println!(
        "touched {n_touched} of {}; half way {} in contact, tips at {mean_lowered:.3} of rest on \
         average; deepest inside: control point {:.4} m, curve {:.4} m; lowest point {lowest:.4} m",
        rest.len(),
        lowered.len(),
        worst.0,
        worst.1
    );
    assert!(n_touched > 100, "the ball touched only {n_touched} blades");
    assert!(
        mean_lowered < 0.75,
        "tips in contact at {mean_lowered} of their rest height"
    );
    assert!(
        worst.0 <= MOVING_TOLERANCE,
        "a control point {} m inside the ball",
        worst.0
    );
    assert!(
        worst.1 <= MOVING_TOLERANCE,
        "the drawn curve {} m inside the ball",
        worst.1
    );

    // Recovery: count the time until every touched blade's tip is back
    // within 10% of its rest height.
    let mut recovered_after = None;
    for step in 0..(6.0 / dt) as usize {
        grass.step(|_| Vec3::ZERO);
        let tips = tip_heights(&grass);
        let low = (0..rest.len())
            .filter(|&i| touched[i] && tips[i] < 0.9 * rest[i])
            .count();
        if low == 0 && recovered_after.is_none() {
            recovered_after = Some((step + 1) as f32 * dt);
        }
        if step + 1 == (5.0 / dt) as usize {
            assert_eq!(
                low, 0,
                "{low} touched blades below 90% of their rest height 5 s after"
            );
        }
    }
    println!("every touched tip within 10% of rest {recovered_after:?} s after the ball left");
}

#[test]
fn a_ball_laid_on_the_meadow_leaves_no_control_point_inside() {
    let (_, grass) = strip(1500);
    let centre = Vec3::new(0.0, RADIUS, 0.0);
    let mut grass = grass.with_colliders(vec![ball(vec![centre], 0.0)]);
    let at = grass.colliders[0].at(0.0);
    let (before, _) = deepest_inside(&grass, &at);
    assert!(
        before > 0.1,
        "the ball should start inside blades ({before})"
    );
    for _ in 0..120 {
        grass.step(|_| Vec3::ZERO);
    }
    let (control, curve) = deepest_inside(&grass, &at);
    let inside = grass
        .poses()
        .filter(|p| p.points[1..].iter().any(|q| at.distance(*q).0 < 0.0))
        .count();
    println!("after 2 s: deepest control point {control:.5} m, curve {curve:.5} m, {inside} blades with a control point inside");
    assert!(
        control <= RESTING_TOLERANCE,
        "a control point {control} m inside the resting ball"
    );
    assert!(
        curve <= RESTING_TOLERANCE,
        "the drawn curve {curve} m inside the resting ball"
    );
    // Roots fixed, edge lengths kept.
    for (b, p) in grass.blades.iter().zip(grass.poses()) {
        assert_eq!(p.points[0], b.rest_point(0));
        for i in 0..3 {
            let rest = (b.rest_point(i + 1) - b.rest_point(i)).length();
            let now = (p.points[i + 1] - p.points[i]).length();
            assert!(
                (now - rest).abs() < 1e-5 * rest.max(1.0),
                "edge {i}: {now} vs {rest}"
            );
        }
    }
}
