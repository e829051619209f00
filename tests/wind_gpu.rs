//! The wind solver on GPU compute against its CPU reference
//! (src/model/wind/mod.rs), on the default device with validation on.

use crate::common;

use common::wind_scenes::{self, behaviour_grid, blowing_source};
use common::{finish, strict_gpu};
use glam::{UVec3, Vec3};
use meadow::analysis::stats::rms_over_fluid;
use meadow::compute::WindPass;
use meadow::gpu::CommandPool;
use meadow::model::contact::{Collider, ColliderKind};
use meadow::model::multigrid::{Start, DEFAULT_V_CYCLES};
use meadow::model::wind::{
    Advection, FaceKind, Gust, Inflow, Obstacle, PressureSolver, Sweep, Turbulence, WindField,
    WindGrid, WindSettings, WindSource,
};

/// Turbulence of intensity 0.3 and a 2 m length scale, drawn from `seed`:
/// what the GPU-against-CPU tests step with.
fn turbulence_2m(seed: u32) -> Turbulence {
    Turbulence {
        intensity: 0.3,
        length_scale: 2.0,
        seed,
        speed: None,
        finest_wavelength: None,
    }
}

fn grid(cells: UVec3) -> WindGrid {
    WindGrid::new(
        cells,
        Vec3::new(-6.0, 0.0, -6.0),
        Vec3::new(12.0, 5.0, 12.0),
    )
    .unwrap()
}

fn two_sources_one_obstacle() -> WindSettings {
    let mut rotating = WindSource::fixed(Vec3::new(-3.0, 1.5, 0.5), Vec3::X, 25.0, 3.0);
    rotating.rotation_speed = 0.8;
    rotating.gust = Gust {
        amplitude: 0.4,
        frequency: 0.7,
        seed: 11,
    };
    let mut moving = WindSource::fixed(
        Vec3::new(2.0, 1.0, -2.0),
        Vec3::new(-1.0, 0.3, 1.0),
        18.0,
        2.5,
    );
    moving.path = vec![
        Vec3::new(2.0, 1.0, -2.0),
        Vec3::new(3.0, 1.5, 2.0),
        Vec3::new(-1.0, 1.0, 3.0),
    ];
    moving.path_speed = 1.5;
    WindSettings {
        sources: vec![rotating, moving],
        inflow: Some(Inflow {
            speed: 2.0,
            heading: 0.0,
            gust: Gust {
                amplitude: 0.3,
                frequency: 0.5,
                seed: 2,
            },
        }),
        obstacles: vec![Obstacle::Box {
            min: Vec3::new(-0.5, 0.0, -1.0),
            max: Vec3::new(0.5, 2.0, 1.0),
        }],
        colliders: vec![
            // A ball rolling round a closed path across the wind, and a
            // walker crossing once: moving obstacles.
            Collider {
                kind: ColliderKind::Sphere,
                radius: 0.8,
                height: 0.0,
                position: Vec3::ZERO,
                path: vec![
                    Vec3::new(-4.0, 0.8, -3.0),
                    Vec3::new(3.0, 0.8, -3.5),
                    Vec3::new(1.0, 0.8, 3.0),
                ],
                path_speed: 2.5,
                closed: true,
                roll: true,
                ..Default::default()
            },
            Collider {
                kind: ColliderKind::Capsule,
                radius: 0.6,
                height: 1.8,
                position: Vec3::ZERO,
                path: vec![Vec3::new(3.0, 0.0, 4.0), Vec3::new(-4.0, 0.0, 1.0)],
                path_speed: 1.4,
                closed: false,
                roll: false,
                ..Default::default()
            },
        ],
        ..Default::default()
    }
}

/// Steps the GPU solver `steps` times (one submission) and reads it back.
fn run_gpu(
    gpu: &meadow::gpu::Gpu,
    grid: WindGrid,
    settings: &WindSettings,
    steps: u32,
    dt: f32,
) -> [Vec<f32>; 3] {
    let commands = CommandPool::new(gpu, "wind test commands").unwrap();
    let mut pass = WindPass::new(gpu, &commands, grid, settings, 0.0).unwrap();
    let rec = commands.begin().unwrap();
    for n in 0..steps {
        pass.record_step(&rec, n as f32 * dt, dt);
    }
    rec.submit_and_wait("wind steps").unwrap();
    pass.read_velocity(gpu, &commands).unwrap()
}

/// The CPU reference after `steps` steps of `dt` from rest.
fn cpu_after(grid: WindGrid, settings: &WindSettings, steps: u32, dt: f32) -> WindField {
    let mut field = WindField::new(grid, settings);
    for _ in 0..steps {
        field.step(settings, dt);
    }
    field
}

fn relative_l2(a: &[Vec<f32>; 3], b: &[Vec<f32>; 3]) -> f64 {
    let mut diff = 0.0f64;
    let mut norm = 0.0f64;
    for axis in 0..3 {
        for (x, y) in a[axis].iter().zip(&b[axis]) {
            diff += ((x - y) as f64).powi(2);
            norm += (*y as f64).powi(2);
        }
    }
    (diff / norm).sqrt()
}

/// GPU and CPU run the same kernels in f32; they differ by rounding (fused
/// multiply-adds, the driver's sin/cos), which semi-Lagrangian advection
/// carries along. Measured on lavapipe (Mesa 22.3.6, llvmpipe 256 bits):
/// 6.0e-7 (pressure from zero each step) and 8.3e-7 (warm-started) after 100
/// steps. The bound leaves a ~12x margin for other drivers' rounding and is orders of magnitude below a real discrepancy (a wrong
/// boundary, a missing barrier or a kernel off by one cell gives > 1e-3).
const GPU_CPU_TOLERANCE: f64 = 1e-5;

/// The default solver, multigrid, with MacCormack's advection.
#[test]
fn gpu_matches_the_cpu_reference_after_100_steps() {
    gpu_matches_the_cpu_reference(PressureSolver::Multigrid, Advection::Maccormack);
}

/// The paper's solver and advection (the default advection).
#[test]
fn gpu_jacobi_matches_the_cpu_reference_after_100_steps() {
    gpu_matches_the_cpu_reference(PressureSolver::Jacobi, Advection::SemiLagrangian);
}

/// A wind pass made again on the same GPU compiles none of its kernels
/// again (gpu/made_once.rs): they outlive the pass that made them, step
/// the same wind bit for bit, and go at teardown with the device (`finish`
/// fails on any object left). A grid with one more multigrid level adds
/// only its tail kernel, specialised to that grid's coarsest level.
#[test]
fn a_wind_pass_made_again_shares_the_kernels_made_first() {
    let gpu = strict_gpu();
    let settings = two_sources_one_obstacle();
    let dt = 1.0 / 60.0;
    let small = grid(UVec3::new(8, 4, 8));
    let first = run_gpu(&gpu, small, &settings, 10, dt);
    let made = gpu.compute_pipelines_made();
    assert!(made > 10, "only {made} compute pipelines made");
    let again = run_gpu(&gpu, small, &settings, 10, dt);
    assert_eq!(
        gpu.compute_pipelines_made(),
        made,
        "the second pass compiled"
    );
    assert_eq!(first, again, "the shared kernels stepped another wind");
    let levels = |cells| {
        WindField::new(grid(cells), &settings)
            .multigrid
            .levels
            .len()
    };
    let larger = UVec3::new(16, 8, 16);
    assert_eq!(levels(larger), levels(small.cells) + 1);
    run_gpu(&gpu, grid(larger), &settings, 1, dt);
    assert_eq!(gpu.compute_pipelines_made(), made + 1);
    finish(gpu);
}

/// A red-black sweep with both colours in one dispatch (`Sweep::Fused`,
/// glsl/wind/mg_sweep.comp) gives the pressure the two half-sweeps give
/// (mg_smooth.comp), in fewer dispatches: each workgroup works the red
/// cells of one cell around its tile out again from the same values. The
/// grid's finest level spans tiles that end short along every axis (36 x
/// 24 x 36 cells in 16 x 20 x 16 tiles), and every step runs its V-cycles
/// (tolerance 0). (Without the cells around the tile, the black cells at
/// its sides read red neighbours never swept, and the wind turns NaN.)
#[test]
fn gpu_fused_sweeps_give_the_split_sweeps_wind_in_fewer_dispatches() {
    let gpu = strict_gpu();
    let grid = grid(UVec3::new(36, 24, 36));
    let dt = 1.0 / 60.0;
    let run = |sweep: Sweep| {
        let settings = WindSettings {
            v_cycles: 2,
            pressure_tolerance: 0.0,
            sweep,
            ..two_sources_one_obstacle()
        };
        let commands = CommandPool::new(&gpu, "wind test commands").unwrap();
        let mut pass = WindPass::new(&gpu, &commands, grid, &settings, 0.0).unwrap();
        let rec = commands.begin().unwrap();
        for n in 0..12 {
            pass.record_step(&rec, n as f32 * dt, dt);
        }
        rec.submit_and_wait("wind steps").unwrap();
        let vel = pass.read_velocity(&gpu, &commands).unwrap();
        (vel, pass.step_dispatches(None), pass.tail_level())
    };
    let (split, split_dispatches, tail) = run(Sweep::Split);
    let (fused, fused_dispatches, _) = run(Sweep::Fused);
    assert!(
        tail >= 2,
        "tail level {tail}: the sweeps run on too few levels"
    );
    assert!(
        split.iter().flatten().any(|v| v.abs() > 1.0),
        "too weak a wind"
    );
    let err = relative_l2(&fused, &split);
    eprintln!("fused against split sweeps, relative L2 after 12 steps: {err:.3e}");
    assert!(err < 1e-6, "relative L2 difference {err:.3e}");
    // One dispatch fewer a sweep: (2 + 2) a level above the tail, in each
    // of the two V-cycles.
    let sweeps = meadow::model::multigrid::PRE_SMOOTH + meadow::model::multigrid::POST_SMOOTH;
    assert_eq!(split_dispatches - fused_dispatches, 2 * tail * sweeps);
    finish(gpu);
}

/// The multigrid with its whole V-cycle in the one-workgroup tail kernel
/// (glsl/wind/mg_tail.glsl from level 0: the pressure and divergence read
/// and written where the kernels keep them), on a grid small enough for
/// every device's shared memory. (With the post-smoothing one sweep short
/// in the tail it differs by 6e-4.)
#[test]
fn gpu_multigrid_in_one_workgroup_matches_the_cpu_reference() {
    let gpu = strict_gpu();
    let grid = grid(UVec3::new(8, 4, 8));
    // One V-cycle a step: several would converge to the same pressure
    // whatever the cycle got wrong.
    let settings = WindSettings {
        v_cycles: 1,
        ..two_sources_one_obstacle()
    };
    let commands = CommandPool::new(&gpu, "wind test commands").unwrap();
    let pass = WindPass::new(&gpu, &commands, grid, &settings, 0.0).unwrap();
    assert_eq!(pass.tail_level(), 0);
    drop(pass);
    drop(commands);
    let dt = 1.0 / 60.0;
    let gpu_vel = run_gpu(&gpu, grid, &settings, 100, dt);
    let cpu = cpu_after(grid, &settings, 100, dt);
    let err = relative_l2(&gpu_vel, &cpu.vel);
    eprintln!("one workgroup: relative L2 GPU vs CPU after 100 steps: {err:.3e}");
    assert!(
        cpu.vel.iter().flatten().any(|v| v.abs() > 1.0),
        "the test wind is too weak to mean anything"
    );
    assert!(err < GPU_CPU_TOLERANCE, "relative L2 difference {err:.3e}");
    finish(gpu);
}

/// The multigrid's start and stop (glsl/wind/mg_start.comp,
/// mg_check.comp): step by step the GPU starts where the CPU reference
/// starts (zero, the last pressure or the last two carried on) and runs
/// the V-cycles it runs, and its histogram counts the steps by them. A
/// start that ignored the last pressure, or a check that never stopped,
/// runs seven cycles where the reference runs three to five.
#[test]
fn gpu_multigrid_starts_and_stops_where_the_cpu_reference_does() {
    const STEPS: u32 = 30;
    let gpu = strict_gpu();
    let grid = grid(UVec3::new(24, 10, 24));
    let settings = two_sources_one_obstacle();
    let commands = CommandPool::new(&gpu, "wind test commands").unwrap();
    let mut pass = WindPass::new(&gpu, &commands, grid, &settings, 0.0).unwrap();
    let mut field = WindField::new(grid, &settings);
    let dt = 1.0 / 60.0;
    let (mut gpu_cycles, mut cpu_cycles) = (Vec::new(), Vec::new());
    let mut mismatches = Vec::new();
    for step in 0..STEPS {
        let rec = commands.begin().unwrap();
        pass.record_step(&rec, step as f32 * dt, dt);
        rec.submit_and_wait("one wind step").unwrap();
        field.step(&settings, dt);
        let solve = pass.read_solve(&gpu, &commands).unwrap();
        let cpu = field.last_solve;
        eprintln!(
            "step {step}: GPU {} cycles from {} ({:.2e} left), CPU {} from {:?} ({:.2e})",
            solve.v_cycles, solve.start, solve.share_left, cpu.v_cycles, cpu.start, cpu.share_left
        );
        let start = match cpu.start {
            Start::Zero => 0,
            Start::Last => 1,
            Start::Extrapolated => 2,
        };
        if (solve.v_cycles, solve.start) != (cpu.v_cycles, start) {
            mismatches.push(step);
        }
        gpu_cycles.push(solve.v_cycles);
        cpu_cycles.push(cpu.v_cycles);
    }
    let solve = pass.read_solve(&gpu, &commands).unwrap();
    drop(pass);
    drop(commands);
    finish(gpu);
    // f32 sums on the GPU against f64 on the CPU may land one cycle
    // apart on a step whose residual sits at the tolerance.
    assert!(
        mismatches.len() <= 1,
        "steps where the GPU's solve differs: {mismatches:?}"
    );
    let mut counted = [0u32; 8];
    for &c in &gpu_cycles[..gpu_cycles.len() - 1] {
        counted[c as usize] += 1;
    }
    assert_eq!(
        &solve.histogram[..8],
        &counted,
        "the histogram of V-cycles per step"
    );
    assert_eq!(solve.steps, STEPS);
    let mut sorted = cpu_cycles.clone();
    sorted.sort();
    assert_eq!(
        cpu_cycles[0], DEFAULT_V_CYCLES,
        "the first step starts from zero"
    );
    // Measured: median 4 (two moving sources and colliders change the
    // wind every step), every step after the third starting warm.
    let median = sorted[STEPS as usize / 2];
    assert!(median <= 4, "median V-cycles {median}");
}

fn gpu_matches_the_cpu_reference(solver: PressureSolver, advection: Advection) {
    let gpu = strict_gpu();
    let grid = grid(UVec3::new(24, 10, 24));
    let settings = WindSettings {
        solver,
        advection,
        ..two_sources_one_obstacle()
    };
    let dt = 1.0 / 60.0;
    if solver == PressureSolver::Multigrid {
        // Level 0 (24x10x24) kernel by kernel, and from level 1
        // (12x5x12; 5,307 floats) or 2 (6x3x6; 831 floats) down to 3x2x3
        // in the tail kernel, on every device.
        let commands = CommandPool::new(&gpu, "wind test commands").unwrap();
        let pass = WindPass::new(&gpu, &commands, grid, &settings, 0.0).unwrap();
        assert!((1..=2).contains(&pass.tail_level()));
    }
    let gpu_vel = run_gpu(&gpu, grid, &settings, 100, dt);
    let cpu = cpu_after(grid, &settings, 100, dt);
    let err = relative_l2(&gpu_vel, &cpu.vel);
    eprintln!("{solver:?}, {advection:?}: relative L2 GPU vs CPU after 100 steps: {err:.3e}");
    // The colliders are part of what is compared: without them the field
    // is far from this one.
    let still = WindSettings {
        colliders: Vec::new(),
        ..settings.clone()
    };
    let collider_effect = relative_l2(&cpu_after(grid, &still, 100, dt).vel, &cpu.vel);
    eprintln!("the colliders change the field by {collider_effect:.3e} (relative L2)");
    assert!(collider_effect > 1e3 * GPU_CPU_TOLERANCE);
    assert!(
        cpu.vel.iter().flatten().any(|v| v.abs() > 1.0),
        "the test wind is too weak to mean anything"
    );
    assert!(err < GPU_CPU_TOLERANCE, "relative L2 difference {err:.3e}");
    // Inside the obstacle the GPU holds exactly zero too.
    for (component, kinds) in gpu_vel.iter().zip(&cpu.faces) {
        for (v, kind) in component.iter().zip(kinds) {
            if *kind == FaceKind::Wall {
                assert_eq!(*v, 0.0);
            }
        }
    }
    finish(gpu);
}

/// Wind over terrain from an oblique heading: a hill and a ridge under a
/// gusting inflow towards 200 degrees (entering by the +x and +z sides).
/// The GPU follows the CPU reference, the cells under the ground hold no
/// through-flow, the buried faces hold the ghost values of the air above
/// (glsl/wind/under_ground.comp), and the terrain changes the field (a
/// solver that ignored it fails the last check).
#[test]
fn gpu_matches_the_cpu_reference_over_terrain_from_any_heading() {
    gpu_matches_the_cpu_reference_over_terrain(None);
}

/// The same with turbulence (glsl/wind/turbulence.comp): the modes' sum on
/// every free face, added before the projection among solids and taken
/// off again by the next step's forces kernel, follows the CPU reference;
/// the turbulence is there (a kernel that added nothing fails that
/// check), and the GPU's field leaves no divergence beside the ground.
#[test]
fn gpu_turbulence_matches_the_cpu_reference_over_terrain() {
    gpu_matches_the_cpu_reference_over_terrain(Some(turbulence_2m(5)));
}

fn gpu_matches_the_cpu_reference_over_terrain(turbulence: Option<Turbulence>) {
    use meadow::model::terrain::{Hill, Ridge, Terrain};
    let gpu = strict_gpu();
    let grid = grid(UVec3::new(24, 12, 24));
    let terrain = Terrain {
        hills: vec![Hill {
            center: [1.5, -2.0],
            height: 1.6,
            half_width: 2.0,
        }],
        ridges: vec![Ridge {
            center: [-3.0, 0.0],
            height: 0.8,
            half_width: 1.0,
            heading: 60.0,
        }],
        ..Terrain::default()
    };
    let settings = WindSettings {
        inflow: Some(Inflow {
            speed: 3.0,
            heading: 200.0,
            gust: Gust {
                amplitude: 0.5,
                frequency: 0.7,
                seed: 2,
            },
        }),
        terrain,
        turbulence,
        ..Default::default()
    };
    let dt = 1.0 / 60.0;
    let gpu_vel = run_gpu(&gpu, grid, &settings, 100, dt);
    let cpu = cpu_after(grid, &settings, 100, dt);
    let flat = WindSettings {
        terrain: Terrain::default(),
        ..settings.clone()
    };
    let over_flat = cpu_after(grid, &flat, 100, dt);
    let err = relative_l2(&gpu_vel, &cpu.vel);
    let terrain_effect = relative_l2(&over_flat.vel, &cpu.vel);
    let count = |k: FaceKind| cpu.faces.iter().flatten().filter(|&&f| f == k).count();
    eprintln!(
        "over terrain, towards 200 degrees: relative L2 GPU vs CPU after 100 steps {err:.3e}; \
         the terrain changes the field by {terrain_effect:.3e}; {} buried faces, {} inflow faces",
        count(FaceKind::Buried),
        count(FaceKind::Inflow)
    );
    assert!(count(FaceKind::Buried) > 100 && count(FaceKind::Inflow) > 100);
    assert!(err < GPU_CPU_TOLERANCE, "relative L2 difference {err:.3e}");
    assert!(terrain_effect > 0.05, "the terrain barely changed the wind");
    for (component, kinds) in gpu_vel.iter().zip(&cpu.faces) {
        for (v, kind) in component.iter().zip(kinds) {
            if *kind == FaceKind::Wall {
                assert_eq!(*v, 0.0);
            }
        }
    }
    // A buried face holds the value of the first free face above it.
    let buried_ghosts = cpu.faces[0]
        .iter()
        .zip(&gpu_vel[0])
        .filter(|(k, _)| **k == FaceKind::Buried)
        .filter(|(_, v)| v.abs() > 0.1)
        .count();
    assert!(
        buried_ghosts > 50,
        "{buried_ghosts} buried faces carry the wind above"
    );
    if turbulence.is_some() {
        let calm = WindSettings {
            turbulence: None,
            ..settings.clone()
        };
        let turbulence_effect = relative_l2(&cpu_after(grid, &calm, 100, dt).vel, &cpu.vel);
        eprintln!("the turbulence changes the field by {turbulence_effect:.3e}");
        assert!(turbulence_effect > 0.1, "{turbulence_effect:.3e}");
        // The projection turned the modes around the ground: the GPU's
        // field leaves no more divergence in the air than the multigrid
        // leaves, against what its last projection began with (the
        // CPU's).
        let before = rms_over_fluid(&cpu.divergence, &cpu.solid);
        let mut on_gpu = cpu.clone();
        on_gpu.vel = gpu_vel.clone();
        let after = on_gpu.rms_divergence() as f64;
        eprintln!("the GPU's field leaves {after:.3e} 1/s of divergence, its projection began with {before:.3e}");
        assert!(after < 1e-3 * before, "{after:e} of {before:e}");
    }
    finish(gpu);
}

/// The viewer's wind keys and gusts (`WindPass::set_drive`): halfway, the
/// inflow strengthens and turns from +x to 30 degrees (entering now by two
/// sides: the faces reclassified) and a gust source drops in; the GPU, changed
/// between submissions, follows the CPU reference stepping with the
/// changed settings, and the change is large (a drive that did not reach
/// the kernels fails both checks).
#[test]
fn a_drive_changed_between_steps_reaches_the_gpu_kernels() {
    let gpu = strict_gpu();
    let grid = grid(UVec3::new(24, 10, 24));
    let before = two_sources_one_obstacle();
    let mut after = before.clone();
    after.inflow.as_mut().unwrap().speed = 3.5;
    after.inflow.as_mut().unwrap().heading = 30.0;
    let mut gust = WindSource::fixed(Vec3::new(3.0, 0.5, 3.0), Vec3::NEG_Z, 30.0, 2.0);
    // Off between two steps (at a step's time, f32 rounding of the two
    // clocks would pick sides).
    gust.off_after = Some(1.21);
    after.sources.push(gust);
    let dt = 1.0 / 60.0;
    // The colliders change too (the viewer's ball steered): the walker
    // goes, and the ball sets off from a new place just after the change
    // (between two steps, as the gust goes off).
    let mut drive_only = after.clone();
    after.colliders.truncate(1);
    after.colliders[0].path = vec![Vec3::new(3.0, 0.8, 3.0), Vec3::new(-4.0, 0.8, 2.0)];
    after.colliders[0].closed = false;
    after.colliders[0].start = 50.5 * dt;
    drive_only.colliders = before.colliders.clone();
    let commands = CommandPool::new(&gpu, "wind test commands").unwrap();
    let mut pass = WindPass::new(&gpu, &commands, grid, &before, 0.0).unwrap();
    let mut cpu = WindField::new(grid, &before);
    let mut unchanged = WindField::new(grid, &before);
    let mut same_colliders = WindField::new(grid, &before);
    for (half, settings) in [(0, &before), (1, &after)] {
        if half == 1 {
            pass.set_drive(&gpu, &commands, after.inflow, &after.sources)
                .unwrap();
            pass.set_colliders(&after.colliders).unwrap();
            assert!(cpu.classify_faces(after.inflow.as_ref()));
            same_colliders.classify_faces(after.inflow.as_ref());
        }
        let rec = commands.begin().unwrap();
        for n in 0..50 {
            pass.record_step(&rec, (half * 50 + n) as f32 * dt, dt);
            cpu.step(settings, dt);
            unchanged.step(&before, dt);
            same_colliders.step(if half == 1 { &drive_only } else { &before }, dt);
        }
        rec.submit_and_wait("wind steps").unwrap();
    }
    let gpu_vel = pass.read_velocity(&gpu, &commands).unwrap();
    let err = relative_l2(&gpu_vel, &cpu.vel);
    let change = relative_l2(&unchanged.vel, &cpu.vel);
    let colliders_change = relative_l2(&same_colliders.vel, &cpu.vel);
    eprintln!(
        "changed drive: GPU vs CPU {err:.3e}; the change itself {change:.3e}, the \
         colliders' part {colliders_change:.3e}"
    );
    assert!(err < GPU_CPU_TOLERANCE, "relative L2 difference {err:.3e}");
    assert!(
        change > 0.05,
        "the drive barely changed the wind: {change:.3e}"
    );
    assert!(
        colliders_change > 1e3 * GPU_CPU_TOLERANCE,
        "the colliders' change is too small to see: {colliders_change:.3e}"
    );
    // A heading that is not a number is refused, naming it.
    let mut lost = after.inflow.unwrap();
    lost.heading = f32::NAN;
    let refused = pass
        .set_drive(&gpu, &commands, Some(lost), &after.sources)
        .unwrap_err()
        .to_string();
    assert!(refused.contains("towards NaN degrees"), "{refused}");
    drop(pass);
    drop(commands);
    finish(gpu);
}

/// The GPU's wind solver run 10,000 steps (1,000 a submission) in a
/// storm (two sources at 200 m/s^2 turning at 2 rad/s, gusts doubling the
/// inflow and the sources): every face stays finite and the air moves. On the GPU on purpose: what it proves is the device's
/// f32 kernels and its long recordings (indirect V-cycles, the solve
/// buffer carried step to step) staying sound, which the CPU reference
/// cannot show; the physics it runs is held to that reference by the
/// short tests above.
#[test]
fn gpu_wind_stays_finite_for_10000_steps_at_the_strongest_settings() {
    let gpu = strict_gpu();
    let grid = grid(UVec3::new(12, 6, 12));
    let mut settings = two_sources_one_obstacle();
    for s in &mut settings.sources {
        s.strength = 200.0;
        s.gust = Gust {
            amplitude: 1.0,
            frequency: 2.0,
            seed: 5,
        };
        s.rotation_speed = 2.0;
    }
    settings.inflow = Some(Inflow {
        speed: 10.0,
        heading: 0.0,
        gust: Gust {
            amplitude: 1.0,
            frequency: 1.0,
            seed: 1,
        },
    });
    let commands = CommandPool::new(&gpu, "wind soak").unwrap();
    let mut pass = WindPass::new(&gpu, &commands, grid, &settings, 0.0).unwrap();
    let dt = 1.0 / 60.0;
    for batch in 0..10 {
        let rec = commands.begin().unwrap();
        for n in 0..1000 {
            pass.record_step(&rec, (batch * 1000 + n) as f32 * dt, dt);
        }
        rec.submit_and_wait("wind soak").unwrap();
    }
    let vel = pass.read_velocity(&gpu, &commands).unwrap();
    assert!(vel.iter().flatten().all(|v| v.is_finite()));
    assert!(
        vel.iter().flatten().any(|v| v.abs() > 0.1),
        "no wind at all"
    );
    drop((pass, commands));
    finish(gpu);
}

/// The GPU solver on the small behaviour-test grid, read back into a CPU
/// `WindField` (same layout) for sampling and divergence.
struct GpuWind<'a> {
    gpu: &'a meadow::gpu::Gpu,
    commands: CommandPool,
    pass: WindPass,
    settings: WindSettings,
    steps: u32,
}

impl<'a> GpuWind<'a> {
    fn new(gpu: &'a meadow::gpu::Gpu, settings: &WindSettings) -> Self {
        let commands = CommandPool::new(gpu, "wind behaviour commands").unwrap();
        let pass = WindPass::new(gpu, &commands, behaviour_grid(), settings, 0.0).unwrap();
        Self {
            gpu,
            commands,
            pass,
            settings: settings.clone(),
            steps: 0,
        }
    }

    fn step(&mut self, n: u32, dt: f32) {
        let rec = self.commands.begin().unwrap();
        for _ in 0..n {
            self.pass.record_step(&rec, self.steps as f32 * dt, dt);
            self.steps += 1;
        }
        rec.submit_and_wait("wind steps").unwrap();
    }

    fn field(&self) -> WindField {
        let mut f = WindField::new(behaviour_grid(), &self.settings);
        f.vel = self.pass.read_velocity(self.gpu, &self.commands).unwrap();
        f
    }

    /// Largest |divergence| of the advected field before projection.
    fn divergence_before(&self) -> f32 {
        let d = self.pass.read_divergence(self.gpu, &self.commands).unwrap();
        d.iter().fold(0.0, |m, x| m.max(x.abs()))
    }
}

fn energy(f: &WindField) -> f64 {
    wind_scenes::kinetic_energy(&f.vel)
}

#[test]
fn gpu_projection_residual_falls_with_jacobi_iterations() {
    let gpu = strict_gpu();
    let mut residual = Vec::new();
    let mut before = 0.0f32;
    for iterations in [5, 20, 80] {
        let settings = WindSettings {
            sources: vec![blowing_source()],
            solver: PressureSolver::Jacobi,
            jacobi_iterations: iterations,
            ..Default::default()
        };
        let mut wind = GpuWind::new(&gpu, &settings);
        wind.step(6, 1.0 / 30.0);
        let mut field = wind.field();
        field.compute_divergence();
        residual.push(field.max_divergence());
        before = before.max(wind.divergence_before());
        drop(wind);
    }
    finish(gpu);
    eprintln!("GPU max |div| before projection {before}, after 5/20/80 Jacobi {residual:?}");
    assert!(before > 0.1, "no divergence to remove: {before}");
    assert!(
        residual[1] < residual[0] && residual[2] < residual[1],
        "{residual:?}"
    );
    assert!(residual[2] < 0.1 * before, "{before} -> {residual:?}");
}

#[test]
fn gpu_obstacle_lee_is_calmer_and_a_rotating_source_turns_the_wind() {
    let gpu = strict_gpu();
    let settings = wind_scenes::wall_in_the_wind();
    let mut wind = GpuWind::new(&gpu, &settings);
    wind.step(150, 1.0 / 30.0);
    let field = wind.field();
    drop(wind);
    let (lee, beside) = wind_scenes::lee_and_beside(|x| field.sample(x));
    assert!(lee < 0.6 * beside, "GPU: lee {lee} vs beside {beside}");
    assert!(beside > 1.0, "GPU: no wind beside the wall: {beside}");

    let mut wind = GpuWind::new(&gpu, &wind_scenes::rotating_source());
    let mut angle_at = Vec::new();
    for _ in 0..4 {
        wind.step(15, 1.0 / 30.0);
        let v = wind.field().sample(Vec3::new(0.0, 1.5, 0.0));
        angle_at.push((-v.z).atan2(v.x));
    }
    drop(wind);
    finish(gpu);
    assert!(
        angle_at.windows(2).all(|w| w[1] > w[0]),
        "GPU: {angle_at:?}"
    );
    assert!(angle_at[3] - angle_at[0] > 0.5, "GPU: {angle_at:?}");
}

#[test]
fn gpu_field_decays_after_its_source_switches_off() {
    let gpu = strict_gpu();
    let mut wind = GpuWind::new(&gpu, &wind_scenes::switched_off_after_one_second());
    wind.step(30, 1.0 / 30.0);
    let at_off = energy(&wind.field());
    let mut last = at_off;
    for n in 0..9 {
        wind.step(10, 1.0 / 30.0);
        let e = energy(&wind.field());
        assert!(
            e <= last * 1.0001,
            "GPU: energy grew by step {}: {last} -> {e}",
            30 + 10 * (n + 1)
        );
        last = e;
    }
    drop(wind);
    finish(gpu);
    assert!(
        last < 0.5 * at_off,
        "GPU: barely decayed: {at_off} -> {last}"
    );
}

/// The multigrid solve on every shipped scene (the paper's 60 x 20 x 60
/// grid, inflows, sources, obstacles): every step leaves at most 1% of the
/// rms divergence that forces and advection made. Measured on lavapipe:
/// at most 0.4% over the first 10 steps of any scene (30 Jacobi iterations
/// leave 60-100%).
#[test]
fn gpu_multigrid_leaves_under_1_percent_of_the_divergence_on_every_shipped_scene() {
    const STEPS: u32 = 10;
    let gpu = strict_gpu();
    let commands = CommandPool::new(&gpu, "multigrid scene commands").unwrap();
    let mut failures = Vec::new();
    let mut scenes_above_floor = 0;
    for (name, _) in meadow::scene::BUILTIN {
        let scene = meadow::scene::Scene::load(name).unwrap();
        let grid = scene.wind_grid().unwrap();
        let settings = WindSettings {
            solver: PressureSolver::Multigrid,
            v_cycles: meadow::model::wind::DEFAULT_V_CYCLES,
            ..scene.wind_settings()
        };
        let mut pass = WindPass::new(&gpu, &commands, grid, &settings, 0.0).unwrap();
        let mut field = WindField::new(grid, &settings);
        let dt = scene.wind.dt;
        let mut worst = 0.0f64;
        let mut above_floor = 0;
        for step in 0..STEPS {
            let rec = commands.begin().unwrap();
            pass.record_step(&rec, step as f32 * dt, dt);
            rec.submit_and_wait("one wind step").unwrap();
            let before = rms_over_fluid(
                &pass.read_divergence(&gpu, &commands).unwrap(),
                &field.solid,
            );
            field.vel = pass.read_velocity(&gpu, &commands).unwrap();
            let after = field.rms_divergence() as f64;
            // A field already divergence-free to f32's rounding (steppe's
            // uniform inflow and divergence-free turbulence: rms 0 1/s
            // before, MacCormack's step carrying a uniform wind exactly,
            // and 1e-6 after) leaves rounding, not a failed solve.
            let speed = field
                .vel
                .iter()
                .flatten()
                .fold(0.0f32, |m, v| m.max(v.abs()));
            let floor = grid.divergence_floor(speed) as f64;
            assert!(
                before > 0.0 || after <= floor,
                "{name}: rms divergence {after:e} after a step that left none to remove (step {step})"
            );
            if after > floor {
                worst = worst.max(after / before);
                above_floor += 1;
            }
        }
        eprintln!(
            "{name}: worst share of the divergence left {:.2}% ({above_floor} of {STEPS} steps above f32's floor)",
            100.0 * worst
        );
        scenes_above_floor += usize::from(above_floor > 0);
        if worst > 0.01 {
            failures.push(format!("{name}: {:.2}%", 100.0 * worst));
        }
    }
    drop(commands);
    finish(gpu);
    assert!(failures.is_empty(), "more than 1% left: {failures:?}");
    // Every scene but the one whose wind is divergence-free as it enters
    // had divergence above the floor to remove.
    assert!(
        scenes_above_floor + 1 >= meadow::scene::BUILTIN.len(),
        "only {scenes_above_floor} scenes left more than rounding"
    );
}

/// A wind window that follows the camera (`[grass.cover]`), moved by
/// whole cells between steps (glsl/wind/shift.comp, then the turbulence
/// added where the faces now are): the GPU follows the CPU reference
/// moved the same way (src/model/wind/window.rs), and the moves matter
/// (the field of a window that stayed differs by far more).
#[test]
fn gpu_moves_the_wind_window_as_the_cpu_reference() {
    let gpu = strict_gpu();
    let grid = grid(UVec3::new(24, 10, 24));
    let commands = CommandPool::new(&gpu, "wind test commands").unwrap();
    // Towards 30 degrees (entering by two sides) and along x (the sides
    // along it walls the turbulence crosses).
    for heading in [30.0, 0.0] {
        let settings = WindSettings {
            inflow: Some(Inflow {
                speed: 4.0,
                heading,
                gust: Gust::default(),
            }),
            turbulence: Some(turbulence_2m(9)),
            moving_window: true,
            ..Default::default()
        };
        let dt = 1.0 / 60.0;
        // Each move after its number of steps: along the wind, against it,
        // across, and one wider than the window (every face new).
        let moves = [
            (10, glam::IVec2::new(2, 1)),
            (10, glam::IVec2::new(-3, 0)),
            (15, glam::IVec2::new(0, 4)),
            (10, glam::IVec2::new(30, -30)),
            (20, glam::IVec2::new(1, -1)),
        ];
        let mut pass = WindPass::new(&gpu, &commands, grid, &settings, 0.0).unwrap();
        assert!(pass.follows_camera());
        let mut cpu = WindField::new(grid, &settings);
        let mut still = WindField::new(grid, &settings);
        let rec = commands.begin().unwrap();
        let mut step = 0;
        for (steps, by) in moves {
            pass.record_shift(&rec, by).unwrap();
            cpu.shift_window(&settings, by);
            for _ in 0..steps {
                pass.record_step(&rec, step as f32 * dt, dt);
                cpu.step(&settings, dt);
                still.step(&settings, dt);
                step += 1;
            }
        }
        rec.submit_and_wait("wind steps with moves").unwrap();
        let gpu_vel = pass.read_velocity(&gpu, &commands).unwrap();
        assert_eq!(pass.grid, cpu.grid);
        let err = relative_l2(&gpu_vel, &cpu.vel);
        let moved = relative_l2(&still.vel, &cpu.vel);
        eprintln!(
            "towards {heading} degrees, the window moved five times over {step} steps: \
             relative L2 GPU vs CPU {err:.3e}; against a window that stayed {moved:.3e}"
        );
        assert!(err < GPU_CPU_TOLERANCE, "relative L2 difference {err:.3e}");
        assert!(moved > 0.1, "{moved:.3e}");
        // The GPU's air is divergence-free to f32's rounding too (the
        // sides along an axis wind included).
        cpu.vel = gpu_vel;
        let speed = cpu.vel.iter().flatten().fold(0.0f32, |m, v| m.max(v.abs()));
        let share = cpu.rms_divergence() / cpu.grid.divergence_floor(speed);
        assert!(
            share < 1.0,
            "towards {heading} degrees: {share} of f32's floor"
        );
        drop(pass);
    }
    // A grid fixed over a field does not move.
    let fixed = WindSettings {
        turbulence: Some(turbulence_2m(9)),
        ..Default::default()
    };
    let mut fixed_pass = WindPass::new(&gpu, &commands, grid, &fixed, 0.0).unwrap();
    let rec = commands.begin().unwrap();
    let refused = fixed_pass.record_shift(&rec, glam::IVec2::ONE).unwrap_err();
    assert!(refused.to_string().contains("[grass.cover]"), "{refused}");
    drop(rec);
    drop((fixed_pass, commands));
    finish(gpu);
}

/// A wind window over terrain moves through the world's heights, the
/// ground's staircase moving through it: two hills, a wind source on one
/// and a still ball on the other, a ball rolling over them, turbulence,
/// and moves that bring hills in and out (and back where it began). After
/// each move the GPU writes the moved grid's classification
/// (`WindPass::record_shift`) and follows the CPU reference
/// (`WindField::shift_window`); the source pushes the air where it stands.
/// With the classification left as it was (the hills' staircase staying
/// where the window was before the move), the GPU leaves the CPU by far
/// more than rounding.
#[test]
fn gpu_moves_a_wind_window_over_terrain_as_the_cpu_reference() {
    use meadow::model::terrain::{Hill, Terrain};
    let gpu = strict_gpu();
    let hill = |x: f32, z: f32| Hill {
        center: [x, z],
        height: 1.6,
        half_width: 2.0,
    };
    let terrain = Terrain {
        hills: vec![hill(1.5, -2.0), hill(-3.0, 2.5)],
        ..Terrain::default()
    };
    // From the ground's lowest to 3.4 m over its highest (1.6 m), in the
    // world's heights.
    let grid = WindGrid::new(
        UVec3::new(24, 10, 24),
        Vec3::new(-6.0, 0.0, -6.0),
        Vec3::new(12.0, 5.0, 12.0),
    )
    .unwrap();
    let on_ground = |x: f32, z: f32, above: f32| Vec3::new(x, terrain.height(x, z) + above, z);
    let ball = on_ground(1.5, -2.0, 0.8);
    let source_at = on_ground(-3.0, 2.5, 0.8);
    let rolling = Collider {
        kind: ColliderKind::Sphere,
        radius: 0.5,
        path: [(-5.0, -4.0), (4.0, -1.0), (0.0, 4.0)]
            .map(|(x, z)| on_ground(x, z, 0.5))
            .to_vec(),
        path_speed: 2.0,
        closed: true,
        roll: true,
        ..Default::default()
    };
    let still = Collider {
        kind: ColliderKind::Sphere,
        radius: 0.8,
        position: ball,
        ..Default::default()
    };
    let settings = WindSettings {
        inflow: Some(Inflow {
            speed: 3.0,
            heading: 30.0,
            gust: Gust::default(),
        }),
        sources: vec![WindSource::fixed(source_at, Vec3::Z, 30.0, 1.2)],
        colliders: vec![still, rolling],
        terrain: terrain.clone(),
        turbulence: Some(turbulence_2m(9)),
        moving_window: true,
        ..Default::default()
    };
    let dt = 1.0 / 60.0;
    // Out past the second hill's top and back over both.
    let moves = [
        (10, glam::IVec2::new(0, 0)),
        (10, glam::IVec2::new(-3, 2)),
        (10, glam::IVec2::new(4, 0)),
        (10, glam::IVec2::new(2, -3)),
        (20, glam::IVec2::new(-3, 1)),
    ];
    let commands = CommandPool::new(&gpu, "wind test commands").unwrap();
    let mut pass = WindPass::new(&gpu, &commands, grid, &settings, 0.0).unwrap();
    let mut cpu = WindField::new(grid, &settings);
    let rec = commands.begin().unwrap();
    let mut step = 0;
    let mut changed = 0;
    for (steps, by) in moves {
        pass.record_shift(&rec, by).unwrap();
        let before = cpu.solid.clone();
        cpu.shift_window(&settings, by);
        changed += cpu
            .solid
            .iter()
            .zip(&before)
            .filter(|(a, b)| a != b)
            .count();
        for _ in 0..steps {
            pass.record_step(&rec, step as f32 * dt, dt);
            cpu.step(&settings, dt);
            step += 1;
        }
    }
    rec.submit_and_wait("wind steps with moves over terrain")
        .unwrap();
    let gpu_vel = pass.read_velocity(&gpu, &commands).unwrap();
    assert_eq!(pass.grid, cpu.grid);
    let err = relative_l2(&gpu_vel, &cpu.vel);
    let pushed = cpu.sample(source_at).z;
    eprintln!(
        "a window over two hills moved four times over {step} steps ({changed} cells changed \
         solid or air on the moves): relative L2 GPU vs CPU {err:.3e}; at the source \
         {pushed:.3} m/s its way"
    );
    assert!(changed > 100, "{changed} cells changed on the moves");
    assert!(err < GPU_CPU_TOLERANCE, "relative L2 difference {err:.3e}");
    assert!(
        pushed > 1.0,
        "at the source the wind is {pushed} m/s its way"
    );
    // The GPU's air is divergence-free to the multigrid's share here too.
    let speed = gpu_vel.iter().flatten().fold(0.0f32, |m, v| m.max(v.abs()));
    let cpu_divergence = cpu.rms_divergence();
    cpu.vel = gpu_vel;
    let gpu_divergence = cpu.rms_divergence();
    eprintln!(
        "rms divergence after the last step: GPU {gpu_divergence:.2e}, CPU {cpu_divergence:.2e} 1/s \
         (f32's floor {:.2e})",
        cpu.grid.divergence_floor(speed)
    );
    assert!(gpu_divergence < 2.0 * cpu_divergence + cpu.grid.divergence_floor(speed));
    drop(pass);
    drop(commands);
    finish(gpu);
}
