//! GPU timing of a frame's phases (timestamp queries) and the report built
//! from them, with the validation layer on.

use crate::common;

use common::{finish, strict_gpu};
use meadow::commands::render::{render_to_dir, Animation, RenderRequest};
use meadow::frame::timing::{FrameTimings, Phase};
use meadow::frame::FrameRecorder;
use meadow::gpu::{GpuOptions, ValidationOptions};
use meadow::render::FrameUniforms;
use meadow::scene::{field, Scene, ViewMode};

/// The sequential phases of a frame: they do not overlap, so together they
/// fit in the frame's own span.
const SEQUENTIAL: [Phase; 6] = [
    Phase::Wind,
    Phase::Grass,
    Phase::Cull,
    Phase::Shadow,
    Phase::Color,
    Phase::Readback,
];

/// `untimed`: phases the device cannot time (not stamped: exactly zero).
fn check_frame(t: &FrameTimings, steps: u64, what: &str, untimed: &[Phase]) {
    for p in Phase::ALL {
        let ms = t.get(p);
        assert!(ms.is_finite() && ms >= 0.0, "{what}: {} = {ms}", p.name());
        assert!(
            ms <= t.frame,
            "{what}: {} {ms} > frame {}",
            p.name(),
            t.frame
        );
    }
    // The cull phase is timed when culling is on (request() turns it on).
    for p in [
        Phase::Shadow,
        Phase::Color,
        Phase::GrassDraw,
        Phase::Readback,
        Phase::Frame,
    ] {
        if untimed.contains(&p) {
            assert_eq!(t.get(p), 0.0, "{what}: {} is untimed here", p.name());
        } else {
            assert!(t.get(p) > 0.0, "{what}: {} was not timed", p.name());
        }
    }
    // Simulation phases are timed when the frame stepped, and are exactly
    // zero (not recorded) when it did not.
    for p in [Phase::Wind, Phase::Grass] {
        assert_eq!(
            t.get(p) > 0.0,
            steps > 0,
            "{what}: {} with {steps} steps",
            p.name()
        );
    }
    let sum: f64 = SEQUENTIAL.iter().map(|&p| t.get(p)).sum();
    assert!(
        sum <= t.frame * 1.0001,
        "{what}: phases {sum} > frame {}",
        t.frame
    );
    assert!(
        t.grass_draw <= t.color,
        "{what}: the grass draw lies inside the colour pass"
    );
}

#[test]
fn every_phase_is_timed_positive_finite_and_within_the_frame() {
    let gpu = strict_gpu();
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.light.shadow_map = 1024;
    let blades = field::generate(&scene.grass, scene.seed).unwrap();
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed).unwrap();
    let mut recorder =
        FrameRecorder::new(&gpu, &scene, (160, 90), 4, &blades, Some(&dynamic)).unwrap();
    let untimed: Vec<Phase> = recorder.untimed_phases().iter().map(|(p, _)| *p).collect();
    // llvmpipe rasterises at the pass's end: a draw inside it is not timed.
    if gpu.info().name.contains("llvmpipe") {
        assert_eq!(untimed, [Phase::GrassDraw]);
    }
    // A frame at rest, one step, and several steps in one frame (the
    // timer's pool grows to hold them).
    for steps in [0u64, 1, 8] {
        let uniforms = FrameUniforms::new(&scene, 160, 90, ViewMode::Shaded, 0.0);
        let frame = recorder.render(&gpu, &uniforms, steps).unwrap();
        let t = frame.timings.expect("lavapipe has timestamps");
        eprintln!("{steps} steps: {t:?}");
        check_frame(&t, steps, &format!("{steps} steps"), &untimed);
        // The statistics of the same frames: one patch per blade the cull
        // pass listed for the colour pass (of 210; some are edge-on).
        let stats = frame.statistics.expect("pipeline statistics");
        let in_view = frame.cull.expect("culling is on by default").in_view;
        assert!(in_view > 100 && in_view <= 210, "{in_view} in view");
        assert_eq!(stats.tessellation_control_patches, in_view as u64);
        // Two triangles a segment, one at each blade's tip.
        assert_eq!(
            stats.geometry_shader_primitives,
            2 * stats.geometry_shader_invocations - stats.tessellation_control_patches
        );
    }
    drop(recorder);
    finish(gpu);
}

fn request(pretend_missing: Vec<String>) -> RenderRequest {
    std::env::set_var("MEADOW_QUIET_VALIDATION", "1");
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.light.shadow_map = 512;
    // Culling on, so that every phase is recorded and timed.
    scene.cull.enabled = true;
    RenderRequest {
        scene,
        width: 96,
        height: 64,
        msaa: 4,
        view: ViewMode::Shaded,
        animation: Animation {
            frames: 3,
            fps: 10.0,
            start: 0.1,
        },
        every: 1,
        gif: false,
        video: None,
        overwrite: false,
        light_waves: false,
        gpu: GpuOptions {
            validation: ValidationOptions::strict(),
            pretend_missing,
            ..Default::default()
        },
    }
}

#[test]
fn report_json_holds_per_phase_medians_wall_time_and_fps() {
    let dir = std::env::temp_dir().join(format!("meadow-timing-{}", std::process::id()));
    let report = render_to_dir(&request(Vec::new()), &dir).unwrap();
    let t = &report.timing;
    assert_eq!(t.frames, 3);
    let gpu = t.gpu_ms.expect("timed");
    assert!(t.gpu_unavailable.is_none());
    if report.device.contains("llvmpipe") {
        let why = &t.phases_unavailable["grass_draw"];
        assert!(why.contains("llvmpipe rasterises"), "{why}");
    }
    for p in Phase::ALL {
        if p == Phase::Cover && report.blade_counts.generated == 0 {
            // No [grass.cover]: no tile pass, nothing to time (0, as a
            // phase not recorded in a frame is).
            assert_eq!(gpu.get(p).map(|s| s.median), Some(0.0));
            continue;
        }
        let Some(s) = gpu.get(p) else {
            assert!(
                t.phases_unavailable.contains_key(p.name()),
                "{} untimed without a reason",
                p.name()
            );
            continue;
        };
        assert!(
            s.median > 0.0 && s.median.is_finite(),
            "{}: {s:?}",
            p.name()
        );
        assert!(s.p95 >= s.median, "{}: {s:?}", p.name());
    }
    let wall = t.wall_frame_ms.unwrap();
    assert!(wall.median > 0.0 && wall.p95 >= wall.median);
    // The wall clock holds the GPU work of the frame.
    assert!(
        wall.median >= gpu.frame.unwrap().median * 0.9,
        "{wall:?} vs {:?}",
        gpu.frame
    );
    assert!((t.fps.unwrap() - 1000.0 / wall.median).abs() < 1e-9);
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap();
    for p in Phase::ALL {
        let entry = &json["timing"]["gpu_ms"][p.name()];
        if t.phases_unavailable.contains_key(p.name()) {
            // Unavailable is null with the reason beside it, never zero.
            assert!(entry.is_null(), "{}: {entry}", p.name());
            assert!(json["timing"]["phases_unavailable"][p.name()].is_string());
        } else if p == Phase::Cover && report.blade_counts.generated == 0 {
            assert_eq!(entry["median"].as_f64(), Some(0.0));
        } else {
            let median = &entry["median"];
            assert!(
                median.as_f64().is_some_and(|v| v > 0.0),
                "{}: {median}",
                p.name()
            );
        }
    }
    assert!(json["timing"]["fps"].as_f64().is_some());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn without_timestamps_the_report_says_unavailable_not_zero() {
    let dir = std::env::temp_dir().join(format!("meadow-no-timestamps-{}", std::process::id()));
    let report = render_to_dir(&request(vec!["timestamps".into()]), &dir).unwrap();
    assert_eq!(report.frames.len(), 3, "the render still runs");
    assert!(report.timing.gpu_ms.is_none());
    let why = report.timing.gpu_unavailable.as_deref().unwrap();
    assert!(why.contains("timestamp"), "{why}");
    assert!(
        report.timing.wall_frame_ms.is_some(),
        "the wall clock is still measured"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("report.json")).unwrap()).unwrap();
    assert!(json["timing"]["gpu_ms"].is_null(), "{}", json["timing"]);
    assert!(json["timing"]["gpu_unavailable"].is_string());
    let _ = std::fs::remove_dir_all(&dir);
}
