//! The wind solver's CPU reference against what docs/method.md section 6 asks of
//! any implementation. (The GPU solver is compared with this reference.)
//! The turbulence's own tests are tests/turbulence_cpu.rs.

use crate::common;

use common::wind_scenes::{self, behaviour_grid, blowing_source, downwind_wind};
use glam::{UVec3, Vec3};
use meadow::model::contact::{Collider, ColliderKind};
use meadow::model::wind::{
    Advection, FaceKind, Gust, Inflow, Obstacle, PressureSolver, WindField, WindGrid, WindSettings,
    WindSource,
};

fn grid() -> WindGrid {
    behaviour_grid()
}

fn kinetic_energy(f: &WindField) -> f64 {
    wind_scenes::kinetic_energy(&f.vel)
}

#[test]
fn projection_removes_divergence_more_with_more_jacobi_iterations() {
    let settings = WindSettings {
        sources: vec![blowing_source()],
        solver: PressureSolver::Jacobi,
        jacobi_iterations: 0,
        ..Default::default()
    };
    let mut field = WindField::new(grid(), &settings);
    for _ in 0..5 {
        field.step(
            &WindSettings {
                jacobi_iterations: 30,
                ..settings.clone()
            },
            1.0 / 30.0,
        );
    }
    // One more step's forces and advection, then project with 5, 20, 80.
    field.add_forces(&settings, 1.0 / 30.0);
    field.advect(1.0 / 30.0, 0.0, None, settings.advection);
    field.compute_divergence();
    let before = field.max_divergence();
    let mut residual = Vec::new();
    for iterations in [5, 20, 80] {
        let mut f = field.clone();
        f.solve_pressure(iterations);
        f.subtract_gradient();
        residual.push(f.max_divergence());
    }
    assert!(before > 0.1, "no divergence to remove: {before}");
    assert!(
        residual[0] < before && residual[1] < residual[0] && residual[2] < residual[1],
        "{before} -> {residual:?}"
    );
    assert!(
        residual[2] < 0.1 * before,
        "80 iterations left {} of {before}",
        residual[2]
    );
}

#[test]
fn obstacle_cells_hold_zero_and_the_lee_is_calmer() {
    let settings = wind_scenes::wall_in_the_wind();
    let mut field = WindField::new(grid(), &settings);
    assert!(
        field.solid.iter().any(|&s| s),
        "the box voxelised to nothing"
    );
    for _ in 0..150 {
        field.step(&settings, 1.0 / 30.0);
    }
    // Every face touching a solid cell is exactly zero.
    for axis in 0..3 {
        for (v, kind) in field.vel[axis].iter().zip(&field.faces[axis]) {
            if *kind == FaceKind::Wall {
                assert_eq!(*v, 0.0);
            }
        }
    }
    let (lee, beside) = wind_scenes::lee_and_beside(|x| field.sample(x));
    assert!(lee < 0.6 * beside, "lee {lee} vs beside {beside}");
    assert!(beside > 1.0, "no wind beside the wall: {beside}");
}

#[test]
fn a_rotating_source_turns_the_wind_at_the_centre() {
    let settings = wind_scenes::rotating_source();
    let mut field = WindField::new(grid(), &settings);
    let dt = 1.0 / 30.0;
    let mut angle_at = Vec::new();
    for step in 1..=60 {
        field.step(&settings, dt);
        if step % 15 == 0 {
            let v = field.sample(Vec3::new(0.0, 1.5, 0.0));
            angle_at.push((-v.z).atan2(v.x));
        }
    }
    // The direction turns from +x toward -z (about +y) as time goes on.
    assert!(angle_at.windows(2).all(|w| w[1] > w[0]), "{angle_at:?}");
    assert!(angle_at[3] - angle_at[0] > 0.5, "{angle_at:?}");
}

#[test]
fn switched_off_the_field_decays_instead_of_growing() {
    let settings = wind_scenes::switched_off_after_one_second();
    let mut field = WindField::new(grid(), &settings);
    let dt = 1.0 / 30.0;
    for _ in 0..30 {
        field.step(&settings, dt);
    }
    let at_off = kinetic_energy(&field);
    let mut last = at_off;
    for n in 0..90 {
        field.step(&settings, dt);
        let e = kinetic_energy(&field);
        assert!(e <= last * 1.0001, "energy grew at step {n}: {last} -> {e}");
        last = e;
    }
    assert!(last < 0.5 * at_off, "barely decayed: {at_off} -> {last}");
}

#[test]
fn strongest_gusting_rotating_wind_stays_finite() {
    let mut a = WindSource::fixed(Vec3::new(-2.0, 1.0, 0.0), Vec3::X, 200.0, 3.0);
    a.rotation_speed = 2.0;
    a.gust = Gust {
        amplitude: 1.0,
        frequency: 2.0,
        seed: 9,
    };
    let mut b = WindSource::fixed(
        Vec3::new(2.0, 1.0, 2.0),
        Vec3::new(-1.0, 0.2, -1.0),
        200.0,
        3.0,
    );
    b.path = vec![
        Vec3::new(2.0, 1.0, 2.0),
        Vec3::new(-2.0, 1.0, 2.0),
        Vec3::new(0.0, 2.0, -3.0),
    ];
    b.path_speed = 3.0;
    let settings = WindSettings {
        sources: vec![a, b],
        inflow: Some(Inflow {
            speed: 10.0,
            heading: 0.0,
            gust: Gust {
                amplitude: 1.0,
                frequency: 1.0,
                seed: 3,
            },
        }),
        obstacles: vec![Obstacle::Sphere {
            center: Vec3::new(0.0, 0.5, 0.0),
            radius: 1.0,
        }],
        ..Default::default()
    };
    let mut field = WindField::new(grid(), &settings);
    for _ in 0..1000 {
        field.step(&settings, 1.0 / 60.0);
    }
    assert!(field.vel.iter().flatten().all(|v| v.is_finite()));
    assert!(field.pressure.iter().all(|v| v.is_finite()));
}

#[test]
fn gusts_moving_paths_and_rotation_follow_their_definitions() {
    let g = Gust {
        amplitude: 0.5,
        frequency: 1.0,
        seed: 4,
    };
    let values: Vec<f32> = (0..100).map(|i| g.factor(i as f32 * 0.05)).collect();
    assert!(
        values.iter().all(|&v| (0.5..=1.5).contains(&v)),
        "gust factor outside 1 +- 0.5"
    );
    assert!(
        values.iter().cloned().fold(0.0, f32::max) - values.iter().cloned().fold(9.0, f32::min)
            > 0.2
    );
    assert_eq!(Gust::default().factor(3.0), 1.0);

    let mut s = WindSource::fixed(Vec3::ZERO, Vec3::X, 1.0, 1.0);
    s.path = vec![Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0)];
    s.path_speed = 2.0;
    assert!((s.at(1.0).0 - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-5);
    assert!(
        (s.at(3.0).0 - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-5,
        "the closed path comes back"
    );
    s.rotation_speed = std::f32::consts::FRAC_PI_2;
    assert!((s.at(1.0).1 - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-5);
}

#[test]
fn bad_wind_input_is_refused_or_warned() {
    assert!(WindGrid::new(UVec3::new(0, 10, 10), Vec3::ZERO, Vec3::ONE)
        .unwrap_err()
        .to_string()
        .contains("not allowed"));
    assert!(WindGrid::new(
        UVec3::new(10, 10, 10),
        Vec3::ZERO,
        Vec3::new(1.0, -1.0, 1.0)
    )
    .is_err());
    assert!(WindGrid::new(UVec3::new(100_000, 1000, 1000), Vec3::ZERO, Vec3::ONE).is_err());
    let g = grid();
    let mut nan = blowing_source();
    nan.strength = f32::NAN;
    assert!(nan.validate(&g).unwrap_err().to_string().contains("NaN"));
    let mut zero_radius = blowing_source();
    zero_radius.radius = 0.0;
    assert!(zero_radius.validate(&g).is_err());
    let mut outside = blowing_source();
    outside.position = Vec3::new(50.0, 1.0, 0.0);
    let warnings = outside.validate(&g).unwrap();
    assert!(
        warnings[0].contains("outside the wind domain"),
        "{warnings:?}"
    );
    // An obstacle that covers no cell blocks nothing: said, as a source
    // outside the grid is; one inside says nothing.
    let far = Obstacle::Sphere {
        center: Vec3::new(500.0, 1.0, 0.0),
        radius: 1.0,
    };
    let near = Obstacle::Sphere {
        center: g.origin + g.size() / 2.0,
        radius: 1.0,
    };
    let settings = WindSettings {
        obstacles: vec![near, far],
        ..Default::default()
    };
    let warnings = settings.check(&g).unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("obstacle 1 covers no cell"),
        "{warnings:?}"
    );
}

fn ball(radius: f32, path: Vec<Vec3>, path_speed: f32) -> Collider {
    Collider {
        kind: ColliderKind::Sphere,
        radius,
        height: 0.0,
        position: path[0],
        path,
        path_speed,
        closed: false,
        roll: true,
        ..Default::default()
    }
}

/// A collider at rest in a steady inflow blocks the air as a fixed solid
/// of its shape does: the air inside it is nearly still and its lee is
/// calm, while the air passes beside it. (Direct forcing, whose faces stay
/// free to the projection: what still flows through is measured here.)
#[test]
fn a_collider_at_rest_blocks_the_wind_as_a_solid_does() {
    let centre = Vec3::new(0.0, 1.0, 0.0);
    let inflow = || WindSettings {
        inflow: Some(Inflow {
            speed: 4.0,
            heading: 0.0,
            gust: Gust::default(),
        }),
        ..Default::default()
    };
    let solid = WindSettings {
        obstacles: vec![Obstacle::Sphere {
            center: centre,
            radius: 1.0,
        }],
        ..inflow()
    };
    let collider = WindSettings {
        colliders: vec![ball(1.0, vec![centre], 0.0)],
        ..inflow()
    };
    let run = |settings: &WindSettings| {
        let mut field = WindField::new(grid(), settings);
        for _ in 0..150 {
            field.step(settings, 1.0 / 30.0);
        }
        let speed = |x: f32, z: f32| field.sample(Vec3::new(x, 1.0, z)).length();
        let lee = (speed(1.5, 0.0) + speed(2.0, 0.0)) / 2.0;
        let beside = (speed(0.0, 2.5) + speed(0.0, -2.5)) / 2.0;
        (speed(0.0, 0.0), lee, beside)
    };
    let (open_centre, open_lee, _) = run(&inflow());
    let (solid_centre, solid_lee, solid_beside) = run(&solid);
    let (centre_speed, lee, beside) = run(&collider);
    println!(
        "centre / lee / beside (m/s): open {open_centre:.2} / {open_lee:.2}; solid {solid_centre:.2} / {solid_lee:.2} / {solid_beside:.2}; collider {centre_speed:.2} / {lee:.2} / {beside:.2}"
    );
    assert!(
        open_centre > 3.5 && open_lee > 3.5,
        "the open inflow is not ~4 m/s"
    );
    assert!(
        centre_speed < 0.15 * open_centre,
        "air through the collider: {centre_speed} m/s"
    );
    assert!(lee < 0.6 * beside, "lee {lee} vs beside {beside}");
    assert!(
        (lee - solid_lee).abs() < 0.25 * open_lee,
        "the collider's lee {lee} m/s, a fixed ball's {solid_lee} m/s"
    );
}

/// A ball moving through still air carries the air inside it along and
/// pushes the air ahead of it; without the forcing the air stays still.
#[test]
fn a_moving_collider_pushes_the_air() {
    let settings = WindSettings {
        colliders: vec![ball(
            1.0,
            vec![Vec3::new(-4.0, 1.0, 0.0), Vec3::new(4.0, 1.0, 0.0)],
            2.0,
        )],
        ..Default::default()
    };
    let mut field = WindField::new(grid(), &settings);
    for _ in 0..60 {
        field.step(&settings, 1.0 / 30.0);
    }
    // At 2 s the ball's centre is at x = 0.
    let at = |x: f32| field.sample(Vec3::new(x, 1.0, 0.0));
    let (inside, ahead, behind) = (at(0.0), at(1.5), at(-1.5));
    println!("air at the ball's centre {inside}, 0.5 m ahead {ahead}, 0.5 m behind {behind}");
    assert!(
        inside.x > 0.8 * 2.0,
        "the air inside the ball moves at {inside}"
    );
    assert!(
        ahead.x > 0.3 && behind.x > 0.3,
        "ahead {ahead}, behind {behind}"
    );
}

/// MacCormack's corrector makes no new extremes: a sharp gust (a block of
/// air at 3 m/s in a 2 m/s wind) carried 60 steps at a Courant number of
/// 0.37 stays within 2..3 m/s on every face, while the unclamped
/// corrector overshoots it (measured here by the same step with the clamp
/// left out: `unclamped`). Advection alone, no projection.
#[test]
fn maccormack_advection_makes_no_new_extremes() {
    let grid = WindGrid::new(
        UVec3::new(48, 4, 6),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(24.0, 2.0, 3.0),
    )
    .unwrap();
    let mut field = WindField::new(grid, &WindSettings::default());
    for (idx, [i, _, _]) in grid.each_face(0) {
        field.vel[0][idx] = if (10..16).contains(&i) { 3.0 } else { 2.0 };
    }
    let dt = 0.37 * 0.5 / 2.5;
    let mut unclamped_max = f32::MIN;
    for _ in 0..60 {
        let before = field.clone();
        field.advect(dt, 0.0, None, Advection::Maccormack);
        unclamped_max = unclamped_max.max(unclamped(&before, dt));
    }
    let free = |axis: usize| {
        field.vel[axis]
            .iter()
            .zip(&field.faces[axis])
            .filter(|(_, k)| **k == FaceKind::Free)
            .map(|(v, _)| *v)
            .collect::<Vec<_>>()
    };
    let (lo, hi) = free(0)
        .iter()
        .fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    eprintln!("after 60 steps: {lo}..{hi} m/s; unclamped the corrector reaches {unclamped_max}");
    assert!(lo >= 2.0 - 1e-5 && hi <= 3.0 + 1e-5, "{lo}..{hi}");
    assert!(free(1).iter().chain(&free(2)).all(|v| v.abs() < 1e-5));
    assert!(unclamped_max > 3.01, "the sharp gust is too easy a case");
}

/// The largest x velocity MacCormack's step from `before` would give
/// without its clamp.
fn unclamped(before: &WindField, dt: f32) -> f32 {
    let mut predicted = before.clone();
    predicted.advect(dt, 0.0, None, Advection::SemiLagrangian);
    let mut max = f32::MIN;
    for (idx, [i, j, k]) in before.grid.each_face(0) {
        if before.faces[0][idx] != FaceKind::Free {
            continue;
        }
        let x = before.grid.face_position(0, i, j, k);
        let v = before.sample(x);
        let again = predicted.sample_component(&predicted.vel[0], 0, x + dt * v);
        max = max.max(predicted.vel[0][idx] + 0.5 * (before.vel[0][idx] - again));
    }
    max
}

/// The spread in time of the downwind wind at blade height (0.4 m), 36 m
/// downwind of a point 2 m inside the inflow side, over its spread there:
/// what a gust keeps of its strength down gust-strip (its grid along the
/// wind and up, 78 x 12 cells, on a strip 1 m wide and 4 cells across, to
/// keep the test short), with `advection`. The gusts' amplitude
/// is 0.1 (the scene's 0.5 makes the gust change itself as it goes: faster
/// air overtakes slower; docs/physics.md), so that what is lost is the
/// scheme's. The first 14 s (the first gusts crossing the 39 m grid at
/// 3 m/s) are left out, then 12 s measured (3.6 periods of the gusts'
/// 0.3 Hz).
fn gust_kept_over_36_m(advection: Advection) -> f64 {
    let mut scene = meadow::scene::Scene::builtin("gust-strip").unwrap();
    scene.grass.meadow[0].size[1] = 1.0;
    scene.wind.cells[2] = 4;
    // The inflow's gusts alone: the scene's turbulence left out.
    scene.wind.turbulence = None;
    let inflow = scene
        .wind
        .inflow
        .as_mut()
        .expect("gust-strip has an inflow");
    inflow.gust.amplitude = 0.1;
    let grid = scene.wind_grid().unwrap();
    let settings = WindSettings {
        advection,
        ..scene.wind_settings()
    };
    let near = Vec3::new(grid.origin.x + 2.0, 0.4, 0.0);
    let far = near + Vec3::new(36.0, 0.0, 0.0);
    let series = downwind_wind(grid, &settings, scene.wind.dt, 14.0, 12.0, &[near, far]);
    let (at_near, at_far) = (&series[0], &series[1]);
    let spread = |v: &[f64]| {
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
    };
    let kept = spread(at_far) / spread(at_near);
    eprintln!(
        "{advection:?}: spread of u at 0.4 m, 2 m in {:.3} m/s, 36 m further {:.3} m/s: {:.0}% kept",
        spread(at_near),
        spread(at_far),
        100.0 * kept
    );
    kept
}

/// Issue 39: MacCormack's advection, the default, keeps most of a gust's
/// strength down gust-strip's 36 m, where the paper's semi-Lagrangian step
/// wears it away (measured on lavapipe: 72% against 5%: docs/physics.md). The bounds: at least 70% kept, as
/// issue 39 asks, and at least 5 times what the semi-Lagrangian step keeps.
#[test]
fn maccormack_keeps_a_gust_down_a_36_m_strip() {
    let maccormack = gust_kept_over_36_m(Advection::Maccormack);
    let semi_lagrangian = gust_kept_over_36_m(Advection::SemiLagrangian);
    assert!(maccormack >= 0.7, "{maccormack:.2}");
    assert!(
        maccormack >= 5.0 * semi_lagrangian,
        "{maccormack:.2} against {semi_lagrangian:.2}"
    );
}
