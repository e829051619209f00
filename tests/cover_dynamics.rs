//! The cover's dynamics near the camera (`compute::CoverDynamics`): the
//! kept tiles stepped by the paper's dynamics, with colliders and on
//! terrain, against the CPU reference, on the default device with
//! validation on.

use crate::common;

use common::cover::*;
use common::{finish, strict_gpu_with};
use glam::Vec2;
use glam::Vec3;
use meadow::compute::cover_tiles::CoverSetup;
use meadow::compute::CoverTilePass;
use meadow::gpu::{Access, CommandPool};
use meadow::model::terrain::Terrain;
use meadow::model::BladeVertex;
use meadow::scene::cover::{self, CoverTiles};
use meadow::scene::{Cover, Grass};

/// Issue 40, item 2: near the camera the cover's blades carry the paper's
/// dynamics (`CoverDynamics`), as the CPU steps them (`GrassField`): the
/// tiles reaching within `simulate_radius` keep their blades' state in the
/// slot their coordinates wrap to; a tile coming in starts at its
/// quasi-static pose, still. Over 30 steps in one wind, the camera moved a
/// tile along x, then 40 in a wind half again as strong (the blades swing
/// to it): the GPU's states follow the CPU's, a kept tile's state carried
/// on, the new column's started where it came in (fails with the states
/// not kept across the move, or not started). Then the tile pass poses
/// every blade: within the radius less the band from its state, beyond
/// it quasi-statically, in the band the two blended
/// (`cover::dynamic_weight`), as the CPU does.
#[test]
fn near_the_camera_the_cover_runs_the_papers_dynamics_as_the_cpu() {
    kept_dynamics_against_the_cpu(&FLAT, &[]);
}

/// The same on hills, a ridge and a height map in a wind window over
/// them: the kept blades rooted on the ground (and held over it by ground
/// contact), each feeling the wind where it stands in the world.
#[test]
fn on_terrain_the_kept_blades_feel_the_wind_where_they_stand_as_the_cpu() {
    kept_dynamics_against_the_cpu(&hilly(), &[]);
}

/// A ball rolling over the hills and a walker crossing the kept tiles
/// press the cover's blades as the CPU's `GrassField` does (the grass step
/// in the cover's slots, its colliders binned over the square it keeps as
/// that moves, one walker crossing the tiles that came in; a tile coming
/// in starts unpressed), and the tile kernel
/// poses them pressed (`pressed_pose`, faded over the band as the angles
/// are). The pressed blades lie lower than the rest. Fails with the tile
/// kernel posing them unpressed (the poses), the kept blades stepped
/// without the colliders, or the bins left where the square first was
/// (the states).
#[test]
fn near_the_camera_a_rolling_ball_presses_the_cover_as_the_cpu() {
    use meadow::model::contact::{Collider, ColliderKind};
    let terrain = hilly();
    let on_ground = |x: f32, z: f32, above: f32| Vec3::new(x, terrain.height(x, z) + above, z);
    let ball = Collider {
        kind: ColliderKind::Sphere,
        radius: 0.8,
        path: vec![on_ground(-1.0, 0.5, 0.8), on_ground(7.0, 2.5, 0.8)],
        path_speed: 6.0,
        roll: true,
        ..Default::default()
    };
    let walker = Collider {
        kind: ColliderKind::Capsule,
        radius: 0.4,
        height: 1.8,
        path: vec![on_ground(3.0, -3.0, 0.0), on_ground(4.0, 4.0, 0.0)],
        path_speed: 3.0,
        ..Default::default()
    };
    // One crossing the tiles that come in at the move (x 12-16 m).
    let newcomer = Collider {
        path: vec![on_ground(15.0, -3.0, 0.0), on_ground(15.0, 4.0, 0.0)],
        ..walker.clone()
    };
    kept_dynamics_against_the_cpu(&terrain, &[ball, walker, newcomer]);
}

fn kept_dynamics_against_the_cpu(
    terrain: &Terrain,
    colliders: &[meadow::model::contact::Collider],
) {
    use meadow::compute::wind_pass::WindInput;
    use meadow::compute::CoverDynamics;
    use meadow::model::grass::{self, GrassState};
    use meadow::model::quasi_static::{quasi_static_angles_within, FAR_ITERATIONS};
    use meadow::model::GrassField;

    let cover = Cover {
        density: Some(1.0),
        view_distance: 12.0,
        seed: Some(21),
        simulate_radius: Some(7.0),
        size: None,
        center: None,
    };
    let grass = Grass::default();
    let seed = cover::seed32(21);
    let (grid, mut field, calm) = steady_wind_over(terrain, Vec3::new(-16.0, 0.0, -16.0), 40.0);
    let strong: Vec<f32> = calm.iter().map(|v| 1.5 * v).collect();
    let dt = 1.0 / 60.0;
    let eyes = [Vec2::new(1.0, 1.0), Vec2::new(5.5, 1.0)];

    let gpu = strict_gpu_with(None);
    let commands = CommandPool::new(&gpu, "cover dynamics commands").unwrap();
    let velocity = wind_buffer(&gpu, &commands, &calm);
    let input = WindInput {
        grid,
        velocity: &velocity,
        canopy: None,
        subgrid: None,
    };
    let setup = meadow::compute::cover_dynamics::CoverDynamicsSetup {
        cover: &cover,
        seed,
        grass: &grass,
        dt,
        camera: eyes[0],
        terrain,
        colliders,
    };
    let mut dynamics = CoverDynamics::new(&gpu, &commands, setup, &input).unwrap();
    let rec = commands.begin().unwrap();
    let mut step = 0u64;
    for (phase, eye) in eyes.iter().enumerate() {
        if phase == 1 {
            rec.uses(&[meadow::gpu::BufferUse::new(
                &velocity,
                Access::TRANSFER_WRITE,
            )]);
            rec.update_buffer(&velocity, 0, bytemuck::cast_slice(&strong));
        }
        dynamics.record_follow(&rec, *eye).unwrap();
        for _ in 0..[30, 40][phase] {
            dynamics.record_step(&rec, meadow::model::contact::step_end_time(step, dt));
            step += 1;
        }
    }
    rec.submit_and_wait("cover dynamics").unwrap();
    let states = dynamics.grass().read_states(&gpu, &commands).unwrap();
    let presses = dynamics.grass().read_presses(&gpu, &commands).unwrap();
    let gpu_substeps = dynamics.grass().substeps();
    let kept = *dynamics.square();
    let stepped = dynamics.blade_count() as usize;

    // The tile pass poses the cover around the last eye from those states.
    let tiles = CoverTiles::around(&cover, eyes[1]);
    let vertices = cover_vertices(&gpu, "posed cover", tiles.blade_count() as usize);
    let frame = unused_frame_uniforms(&gpu);
    let mut pass = CoverTilePass::new(
        &gpu,
        &commands,
        CoverSetup {
            states: Some(dynamics.states()),
            presses: dynamics.presses(),
            far_poses: dynamics.far_poses(),
            ..posing(
                &cover,
                &grass,
                &vertices,
                (&velocity, grid),
                &frame,
                terrain,
            )
        },
    )
    .unwrap();
    pass.set_dynamics(Some(&kept), eyes[1]);
    let rec = commands.begin().unwrap();
    pass.record(&rec, &tiles).unwrap();
    rec.submit_and_wait("cover tiles").unwrap();
    let posed: Vec<BladeVertex> = vertices
        .read_back(&gpu, &commands, tiles.blade_count() as usize * 4)
        .unwrap();
    drop((pass, vertices, frame, dynamics, velocity, commands));
    finish(gpu);

    // The CPU: the same slots, tiles coming in started at their
    // quasi-static pose (the far field's iterations, as the GPU's).
    let per_tile = kept.per_tile;
    let mut cpu = GrassField::new(vec![Default::default(); stepped], dt)
        .unwrap()
        .with_colliders(colliders.to_vec());
    let mut held: Vec<Option<[i32; 2]>> = vec![None; kept.tile_count() as usize];
    let mut substeps = None;
    let mut entered = [0usize; 2];
    for (phase, eye) in eyes.iter().enumerate() {
        let wind = if phase == 0 { &calm } else { &strong };
        let mut start = 0;
        for axis in 0..3 {
            let n = field.vel[axis].len();
            field.vel[axis].copy_from_slice(&wind[start..start + n]);
            start += n;
        }
        let square = cover::kept_tiles(&cover, *eye);
        for n in 0..square.tile_count() as u32 {
            let tile = square.tile(n);
            let slot = cover::state_slot(tile, square.side) as usize;
            if held[slot] == Some(tile) {
                continue;
            }
            held[slot] = Some(tile);
            entered[phase] += 1;
            for index in 0..per_tile {
                let b =
                    cover::grass_blade(terrain, seed, &grass.shape, &grass.dynamics, tile, index)
                        .unwrap();
                let (angle, _) =
                    quasi_static_angles_within(&b, field.sample(b.rest_point(3)), FAR_ITERATIONS);
                let i = slot * per_tile as usize + index as usize;
                cpu.blades[i] = b;
                cpu.states[i] = GrassState {
                    angle,
                    velocity: [0.0; 4],
                };
                cpu.pressed[i] = Default::default();
            }
        }
        // The GPU's pass counts its substeps from the blades it was made
        // with, raised by any stiffer blade coming in.
        let needed = grass::substeps(&cpu.blades, dt).unwrap();
        let n = substeps.map_or(needed, |n: u32| n.max(needed));
        substeps = Some(n);
        cpu.substeps = n;
        for _ in 0..[30, 40][phase] {
            cpu.step(|x| field.sample(x));
        }
    }
    assert_eq!(entered, [25, 5], "tiles started in each phase");
    assert_eq!(
        Some(gpu_substeps),
        substeps,
        "substeps after the tiles came in"
    );
    let mut differs = 0.0f32;
    let mut swung = 0.0f32;
    for (g, c) in states.iter().zip(&cpu.states) {
        for m in 0..4 {
            differs = differs.max((g.angle[m] - c.angle[m]).abs());
            swung = swung.max(c.velocity[m].abs());
        }
    }
    eprintln!(
        "{stepped} kept blades: GPU and CPU angles within {differs:e} rad; swinging at up to {swung} rad/s"
    );
    assert!(swung > 0.1, "the blades barely swing: {swung} rad/s");
    assert!(differs < 1e-4, "GPU and CPU states differ by {differs} rad");
    if !colliders.is_empty() {
        let pressed_differs = presses
            .iter()
            .zip(&cpu.pressed)
            .map(|(g, c)| (g.pressed - c.pressed).abs())
            .fold(0.0f32, f32::max);
        let pressed = cpu.pressed.iter().filter(|p| p.pressed > 0.1).count();
        // How high each kept tip stands over its root, against its rest
        // height: the pressed blades' and the others' means.
        let mut lowered = [(0.0f32, 0usize); 2];
        for (i, pose) in cpu.poses().enumerate() {
            let b = &cpu.blades[i];
            let stands =
                (pose.points[3].y - b.rest_point(0).y) / (b.rest_point(3).y - b.rest_point(0).y);
            let k = (cpu.pressed[i].pressed > 0.1) as usize;
            lowered[k].0 += stands;
            lowered[k].1 += 1;
        }
        let [free, under] = lowered.map(|(sum, n)| sum / n.max(1) as f32);
        eprintln!(
            "{pressed} kept blades pressed over 0.1 (GPU and CPU pressed states within {pressed_differs:e}); \
             their tips stand at {under:.2} of their rest height, the others' at {free:.2}"
        );
        assert!(pressed >= 10, "{pressed} blades pressed");
        assert!(pressed_differs < 1e-5, "{pressed_differs}");
        assert!(under < free - 0.2, "pressed {under}, free {free}");
    } else {
        assert!(
            presses.is_empty(),
            "a pass made without colliders keeps pressed states"
        );
    }

    // The tile pass's pose, blade by blade: the simulated square's blades
    // from their state (their pressing faded out over the band inside the
    // radius), the others quasi-static.
    let r = cover.simulate_radius();
    let mut counts = [0usize; 3];
    let mut posed_pressed = 0;
    let mut worst = 0.0f32;
    for (n, (tile, index)) in tiles.blades().enumerate() {
        let b =
            cover::grass_blade(terrain, seed, &grass.shape, &grass.dynamics, tile, index).unwrap();
        let root = b.rest_point(0);
        let fade = cover::pressed_fade(r, Vec2::new(root.x, root.z).distance(eyes[1]));
        let k = [tile[0] - kept.origin[0], tile[1] - kept.origin[1]];
        let in_square = k.iter().all(|&a| (0..kept.side as i32).contains(&a));
        let (angle, pressed, kind) = if in_square {
            let slot = cover::state_slot(tile, kept.side);
            let kept = (slot * per_tile + index) as usize;
            let pressed = presses.get(kept).map_or(0.0, |p| p.pressed);
            (
                states[kept].angle,
                fade * pressed,
                1 + (fade >= 1.0) as usize,
            )
        } else {
            let (balance, _) =
                quasi_static_angles_within(&b, field.sample(b.rest_point(3)), FAR_ITERATIONS);
            let (still, _) = cover::held_above_ground(terrain, &b, balance);
            (still, 0.0, 0)
        };
        counts[kind] += 1;
        posed_pressed += (pressed > 0.01) as usize;
        let cpu_pose = grass::vertices(&b, &grass::pressed_pose(&b, angle, pressed));
        for (g, c) in posed[4 * n..4 * n + 4].iter().zip(&cpu_pose) {
            let at = |v: &BladeVertex| Vec3::from_slice(&v.position[..3]);
            worst = worst.max(at(g).distance(at(c)));
        }
    }
    eprintln!(
        "posed: {} quasi-static, {} from their state with their pressing faded, {} from their state ({posed_pressed} pressed); \
         GPU and CPU within {worst:e} m",
        counts[0], counts[1], counts[2]
    );
    assert!(counts.iter().all(|&c| c > 10), "{counts:?}");
    assert_eq!(
        posed_pressed > 0,
        !colliders.is_empty(),
        "{posed_pressed} posed pressed"
    );
    assert!(worst < 1e-4, "the tile pass's poses differ by {worst} m");
}

/// A tile coming into the simulated square with a blade stiffer than any
/// stepped so far raises the substeps for all, so explicit Euler stays
/// stable for it (`model::grass::substeps`); they never fall. Over a
/// flight of 60 tiles with a wide stiffness range, the GPU pass's
/// substeps are the CPU's count over every blade kept so far, at each
/// move (fails with the count left at the first square's).
#[test]
fn a_stiffer_blade_coming_in_raises_the_substeps() {
    use meadow::compute::wind_pass::WindInput;
    use meadow::compute::CoverDynamics;
    use meadow::model::grass;
    use meadow::scene::GrassDynamics;

    // One blade a tile, 3 x 3 tiles kept.
    let cover = Cover {
        density: Some(0.07),
        view_distance: 8.0,
        seed: Some(5),
        simulate_radius: Some(2.0),
        size: None,
        center: None,
    };
    let grass = Grass {
        dynamics: GrassDynamics {
            tip_stiffness: [5e-3, 0.2],
            ..GrassDynamics::default()
        },
        ..Grass::default()
    };
    let seed = cover::seed32(5);
    let dt = 1.0 / 60.0;
    let (grid, _, calm) = steady_wind(Vec3::new(-16.0, 0.0, -16.0), 40.0);
    let gpu = strict_gpu_with(None);
    let commands = CommandPool::new(&gpu, "cover substeps commands").unwrap();
    let velocity = wind_buffer(&gpu, &commands, &calm);
    let input = WindInput {
        grid,
        velocity: &velocity,
        canopy: None,
        subgrid: None,
    };
    let eye = |n: usize| Vec2::new(0.5 + 4.0 * n as f32, 0.5);
    let setup = meadow::compute::cover_dynamics::CoverDynamicsSetup {
        cover: &cover,
        seed,
        grass: &grass,
        dt,
        camera: eye(0),
        terrain: &FLAT,
        colliders: &[],
    };
    let mut dynamics = CoverDynamics::new(&gpu, &commands, setup, &input).unwrap();
    let kept_blades = |camera: Vec2| -> Vec<grass::GrassBlade> {
        let square = cover::kept_tiles(&cover, camera);
        square
            .blades()
            .map(|(tile, index)| {
                cover::grass_blade(&FLAT, seed, &grass.shape, &grass.dynamics, tile, index).unwrap()
            })
            .collect()
    };
    let first = grass::substeps(&kept_blades(eye(0)), dt).unwrap();
    assert_eq!(dynamics.grass().substeps(), first);
    let mut expected = first;
    let rec = commands.begin().unwrap();
    for n in 1..=60 {
        dynamics.record_follow(&rec, eye(n)).unwrap();
        dynamics.record_step(&rec, meadow::model::contact::step_end_time(n as u64, dt));
        expected = expected.max(grass::substeps(&kept_blades(eye(n)), dt).unwrap());
        assert_eq!(dynamics.grass().substeps(), expected, "after move {n}");
    }
    rec.submit_and_wait("cover flight").unwrap();
    let states = dynamics.grass().read_states(&gpu, &commands).unwrap();
    drop((dynamics, velocity, commands));
    finish(gpu);
    eprintln!("substeps: {first} for the first square, {expected} after the flight");
    assert!(
        expected > first,
        "no blade came in stiffer: the test tells nothing"
    );
    assert!(
        states.iter().flat_map(|s| s.angle).all(|a| a.is_finite()),
        "a kept blade's state is not finite"
    );
}
