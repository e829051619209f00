//! The `meadow` binary: bad input gives one clear line and a non-zero exit
//! and leaves no frame behind; a good run writes the frame and the report.

mod common;

use std::process::{Command, Output};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use image::ImageEncoder;

use common::binary::{
    files_in, interrupted_render, meadow, read_json, send_sigint, spawn_meadow, spawn_meadow_to,
    temp_out,
};

fn assert_succeeded(result: &Output) {
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
}

/// Fails with exactly one stderr line containing `fragment`, and no frame.
fn assert_refused(args: &[&str], env: &[(&str, &str)], fragment: &str) {
    let out = temp_out(&format!("refused-{}", fragment.len()));
    let out_s = out.to_str().unwrap().to_string();
    let mut full: Vec<&str> = args.to_vec();
    full.extend(["--out", &out_s]);
    let result = meadow(&full, env);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success(), "{args:?} succeeded");
    assert!(
        stderr.contains(fragment),
        "{args:?}: stderr {stderr:?} lacks {fragment:?}"
    );
    assert_eq!(
        stderr.trim_end().lines().count(),
        1,
        "{args:?}: not one line: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        !out.join("frame_0000.png").exists(),
        "{args:?} left a frame"
    );
    let left = files_in(&out);
    assert!(left.is_empty(), "{args:?} left {left:?}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn unknown_scene_is_refused() {
    assert_refused(
        &["render", "--scene", "no-such-scene"],
        &[],
        "unknown scene \"no-such-scene\"",
    );
}

#[test]
fn zero_and_absurd_sizes_are_refused() {
    assert_refused(
        &["render", "--width", "0"],
        &[],
        "--width 0 is not allowed, use a whole number from 1 to 16384",
    );
    assert_refused(
        &["render", "--width", "100000"],
        &[],
        "--width 100000 is not allowed",
    );
    assert_refused(
        &["render", "--height", "0"],
        &[],
        "--height 0 is not allowed",
    );
}

#[test]
fn msaa_that_is_not_a_sample_count_is_refused() {
    assert_refused(
        &["render", "--msaa", "3"],
        &[],
        "--msaa 3 is not a sample count",
    );
}

#[test]
fn bad_animation_settings_are_refused() {
    assert_refused(
        &["render", "--frames", "0"],
        &[],
        "--frames 0 is not allowed",
    );
    assert_refused(&["render", "--fps", "0"], &[], "--fps 0 is not allowed");
    assert_refused(&["render", "--fps", "NaN"], &[], "--fps NaN is not allowed");
    assert_refused(
        &["render", "--start", "-1"],
        &[],
        "--start -1 is not allowed",
    );
    assert_refused(
        &["render", "--every", "0"],
        &[],
        "--every 0 is not allowed, use a whole number from 1 to 100000",
    );
}

#[test]
fn every_kth_frame_is_written_with_a_gif_of_them() {
    let out = temp_out("every");
    let result = meadow(
        &[
            "render",
            "--scene",
            "fig10-few-bunches",
            "--frames",
            "7",
            "--every",
            "3",
            "--width",
            "96",
            "--height",
            "64",
            "--validation",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert_succeeded(&result);
    // Not a terminal: no progress bar (nor anything else) on stderr.
    assert_eq!(String::from_utf8_lossy(&result.stderr), "");
    let report = read_json(&out.join("report.json"));
    assert_eq!(
        report["frames"],
        serde_json::json!(["frame_0000.png", "frame_0003.png", "frame_0006.png"])
    );
    assert_eq!(report["gif"], "animation.gif");
    assert_eq!(report["interrupted"], false);
    use image::AnimationDecoder;
    let gif = std::io::BufReader::new(std::fs::File::open(out.join("animation.gif")).unwrap());
    let frames = image::codecs::gif::GifDecoder::new(gif)
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap();
    assert_eq!(frames.len(), 3);
    // 3 frames of 1/30 s apart: 10 hundredths of a second each.
    let (num, den) = frames[0].delay().numer_denom_ms();
    assert_eq!(num / den, 100);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn zero_blades_are_refused() {
    assert_refused(
        &["render", "--blades", "0"],
        &[],
        "--blades 0 is not allowed",
    );
}

/// `meadow wind` takes the solver's settings from the command line, refuses
/// them by the flags' names, and warns when the projection left most of
/// the divergence (as 30 Jacobi iterations do on the default grid).
#[test]
fn wind_takes_solver_flags_and_says_when_the_projection_falls_short() {
    assert_refused(
        &["wind", "--cells", "60,20"],
        &[],
        "--cells 60,20 has 2 values, use exactly 3",
    );
    assert_refused(
        &["wind", "--cells", "5000,20,60"],
        &[],
        "--cells 5000,20,60 (cells[0]) 5000 is not allowed, use 1..=4096",
    );
    assert_refused(
        &["wind", "--jacobi-iterations", "20000"],
        &[],
        "--jacobi-iterations 20000 is not allowed, use a whole number from 0 to 10000",
    );
    let out = temp_out("wind-flags");
    let result = meadow(
        &[
            "wind",
            "--cells",
            "24,10,24",
            "--jacobi-iterations",
            "2",
            "--steps",
            "10",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert_succeeded(&result);
    let report = read_json(&out.join("wind_report.json"));
    assert_eq!(report["cells"], serde_json::json!([24, 10, 24]));
    assert_eq!(report["jacobi_iterations"], 2);
    let warned = report["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .any(|w| w.as_str().unwrap().contains("the projection left"));
    assert!(warned, "{report}");
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(
        stderr.contains("meadow: warning: the projection left"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// `meadow wind` draws its slices as SVG a person can read: axes in metres,
/// a colour bar in m/s, the plane in the title, the obstacles outlined in
/// white and the grass in green; `--coupling two-way` steps the grass with
/// the wind and says so in the title and the report.
#[test]
fn wind_slices_have_axes_a_colour_bar_and_outlines() {
    for coupling in ["one-way", "two-way"] {
        let out = temp_out(&format!("wind-slices-{coupling}"));
        let result = meadow(
            &[
                "wind",
                "--scene",
                "fig13-obstacles",
                "--cells",
                "24,10,24",
                "--steps",
                "4",
                "--coupling",
                coupling,
                "--out",
                out.to_str().unwrap(),
            ],
            &[],
        );
        assert_succeeded(&result);
        assert_eq!(
            read_json(&out.join("wind_report.json"))["coupling"],
            coupling
        );
        // The vertical slice through the middle passes beside every obstacle.
        for (name, plane, axis, obstacles) in [
            (
                "wind_horizontal.svg",
                "horizontal slice at height y = 0.60 m",
                "z (m)",
                3,
            ),
            (
                "wind_vertical.svg",
                "vertical slice at z = 0.00 m",
                "height y (m)",
                0,
            ),
        ] {
            let svg = std::fs::read_to_string(out.join(name)).unwrap();
            for text in [
                plane,
                axis,
                "x (m)",
                "wind speed (m/s)",
                &format!("{coupling} coupling"),
            ] {
                assert!(svg.contains(text), "{name} has no {text:?}");
            }
            // Obstacles in white, grass in green, each a path of its own.
            let outlined = svg.matches("stroke=\"#FFFFFF\" stroke-width=\"2\"").count();
            assert_eq!(outlined, obstacles, "{name}: obstacles outlined");
            assert_eq!(
                svg.matches("stroke=\"#28C828\"").count(),
                1,
                "{name}: grass outline"
            );
        }
        let _ = std::fs::remove_dir_all(&out);
    }
}

/// `meadow wind --v-cycles` picks the multigrid solve: the report names it,
/// the projection removes nearly all the divergence and nothing warns; a
/// count of 0 and both solvers at once are refused by the flags' names.
/// `--advection` picks the advection, timed beside the other.
#[test]
fn wind_v_cycles_pick_multigrid_which_removes_the_divergence() {
    assert_refused(
        &["wind", "--v-cycles", "0"],
        &[],
        "--v-cycles 0 is not allowed, use a whole number from 1 to 100",
    );
    assert_refused(
        &["wind", "--v-cycles", "3", "--jacobi-iterations", "30"],
        &[],
        "--jacobi-iterations and --v-cycles pick different pressure solvers; give one",
    );
    let out = temp_out("wind-multigrid");
    let result = meadow(
        &[
            "wind",
            "--cells",
            "24,10,24",
            "--v-cycles",
            "6",
            "--advection",
            "maccormack",
            "--steps",
            "10",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert_succeeded(&result);
    let report = read_json(&out.join("wind_report.json"));
    assert_eq!(report["solver"], "multigrid");
    assert_eq!(report["v_cycles"], 6);
    let before = report["rms_divergence_before"].as_f64().unwrap();
    let after = report["rms_divergence_after"].as_f64().unwrap();
    assert!(after < 0.01 * before, "{before} -> {after}");
    assert_eq!(report["warnings"], serde_json::json!([]), "{report}");
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(stdout.contains("6 multigrid V-cycles"), "{stdout}");
    // Both solvers over the same steps, side by side: on the same wind the
    // multigrid leaves far less than the paper's 30 Jacobi iterations.
    let solvers = report["solvers"].as_array().unwrap();
    let left = |i: usize| {
        let s = &solvers[i];
        assert_eq!(s["steps"], 10);
        s["rms_divergence_after"].as_f64().unwrap() / s["rms_divergence_before"].as_f64().unwrap()
    };
    assert_eq!(solvers.len(), 2);
    assert_eq!(
        (&solvers[0]["solver"], &solvers[0]["iterations"]),
        (&"multigrid".into(), &6.into())
    );
    assert_eq!(
        (&solvers[1]["solver"], &solvers[1]["iterations"]),
        (&"jacobi".into(), &30.into())
    );
    assert!(left(0) < 0.01 && left(1) > 10.0 * left(0), "{solvers:?}");
    // MacCormack's advection (--advection overrides the scene's) timed
    // beside the paper's over the same steps (lavapipe has timestamps).
    assert_eq!(report["advection"], "maccormack");
    let cost = &report["advection_cost"];
    assert_eq!(cost["steps"], 10);
    let ms = |k: &str| cost[k].as_f64().unwrap();
    let ratio = ms("step_ms_median_maccormack") / ms("step_ms_median_semi_lagrangian");
    assert!((ms("ratio") - ratio).abs() < 1e-9 && ratio > 0.0, "{cost}");
    assert!(stdout.contains("MacCormack's advection"), "{stdout}");
    let _ = std::fs::remove_dir_all(&out);
}

/// `render --blades` reads counts as `bench --blades` does (50k, 1.5m).
#[test]
fn render_reads_blade_counts_as_bench_does() {
    let out = temp_out("blades-2k");
    let result = meadow(
        &[
            "render",
            "--scene",
            "fig10-few-bunches",
            "--blades",
            "2k",
            "--shadow-map",
            "0",
            "--width",
            "64",
            "--height",
            "36",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert_succeeded(&result);
    let report = read_json(&out.join("report.json"));
    assert_eq!(report["blades"], 2000);
    let _ = std::fs::remove_dir_all(&out);
    assert_refused(
        &["render", "--blades", "1.5x"],
        &[],
        "blade count \"1.5x\" is not a count, write e.g. 50k, 1.5m or 1200",
    );
}

/// A flag's value out of range is refused by the flag's name, not by the
/// scene field it sets.
#[test]
fn flags_out_of_range_are_refused_by_their_own_name() {
    assert_refused(
        &["render", "--shadow-map", "20000"],
        &[],
        "--shadow-map 20000 is not allowed, use a whole number from 0 to 16384",
    );
    assert_refused(
        &["bench", "--shadow-map", "20000"],
        &[],
        "--shadow-map 20000 is not allowed, use a whole number from 0 to 16384",
    );
    // Fewer blades than patches would leave a patch empty.
    assert_refused(
        &["render", "--scene", "fig10-few-bunches", "--blades", "1"],
        &[],
        "--blades 1 is fewer than the scene's 3 patches of grass",
    );
}

#[test]
fn occlusion_asked_with_culling_off_is_refused() {
    assert_refused(
        &["render", "--cull", "off", "--occlusion", "on"],
        &[],
        "--occlusion on is part of culling, which is off",
    );
}

#[test]
fn a_device_without_tessellation_is_refused_by_name() {
    assert_refused(
        &["render", "--width", "64", "--height", "64"],
        &[("MEADOW_PRETEND_MISSING", "tessellationShader")],
        "lacks tessellationShader",
    );
    assert_refused(
        &["render", "--width", "64", "--height", "64"],
        &[("MEADOW_PRETEND_MISSING", "geometryShader")],
        "lacks geometryShader",
    );
}

#[test]
fn no_vulkan_driver_is_refused_with_what_to_install() {
    let missing = "/nonexistent/meadow-no-driver.json";
    assert_refused(
        &["render", "--width", "64", "--height", "64"],
        &[("VK_ICD_FILENAMES", missing), ("VK_DRIVER_FILES", missing)],
        "no Vulkan device found; run scripts/ensure-vulkan",
    );
}

#[test]
fn an_unknown_device_name_is_refused() {
    assert_refused(
        &["render", "--device", "no-such-gpu-xyz"],
        &[],
        "no Vulkan device name contains",
    );
}

#[test]
fn render_writes_frame_and_report_with_validation_clean() {
    let out = temp_out("ok");
    let result = meadow(
        &[
            "render",
            "--scene",
            "fig10-few-bunches",
            "--width",
            "160",
            "--height",
            "90",
            "--validation",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert_succeeded(&result);
    let png = image::open(out.join("frame_0000.png")).expect("a readable PNG");
    assert_eq!((png.width(), png.height()), (160, 90));
    let report = read_json(&out.join("report.json"));
    assert_eq!(report["validation"]["enabled"], true);
    assert_eq!(report["validation"]["errors"], 0);
    assert_eq!(report["blades"], 210);
    let msaa = report["msaa_used"].as_u64().unwrap();
    assert!(msaa.is_power_of_two() && msaa <= 8, "msaa_used {msaa}");
    assert_eq!(report["msaa_requested"], 8);
    assert!(report["device"].as_str().is_some_and(|d| !d.is_empty()));
    // Each pass tessellated the blades the cull pass listed for it (the
    // orientation test leaves out some seen edge-on).
    let counts = &report["cull_counts"];
    let in_view = counts["in_view"].as_u64().unwrap();
    assert!(in_view > 100 && in_view <= 210, "{in_view} in view");
    let stats = &report["pipeline_statistics"];
    assert_eq!(stats["tessellation_control_patches"], in_view);
    assert!(stats["geometry_shader_primitives"].as_u64().unwrap() >= in_view * 2 * 3);
    let shadow = &report["shadow_pipeline_statistics"];
    assert_eq!(
        shadow["tessellation_control_patches"],
        counts["shadow_casters"]
    );
    let casters = counts["shadow_casters"].as_u64().unwrap();
    assert!(casters > 0);
    assert!(shadow["geometry_shader_invocations"].as_u64().unwrap() >= 3 * casters);
    let _ = std::fs::remove_dir_all(&out);
}

/// What a render leaves is enough to redo it: report.json holds the command
/// line, the shadow-map size and the camera, and scene.toml the scene as
/// rendered, overrides applied; rendering that file gives the same frames.
#[test]
fn a_render_can_be_redone_from_the_scene_it_leaves() {
    let first = temp_out("redo-first");
    let again = temp_out("redo-again");
    let args = [
        "render",
        "--scene",
        "fig10-few-bunches",
        "--blades",
        "300",
        "--seed",
        "7",
        "--shadow-map",
        "512",
        "--width",
        "96",
        "--height",
        "54",
        "--msaa",
        "1",
        "--frames",
        "2",
        "--fps",
        "10",
        "--start",
        "0.5",
        "--view",
        "motion",
    ];
    let mut with_out = args.to_vec();
    with_out.extend(["--out", first.to_str().unwrap()]);
    assert_succeeded(&meadow(&with_out, &[]));
    let report = read_json(&first.join("report.json"));
    assert_eq!(report["scene_file"], "scene.toml");
    assert_eq!(report["shadow_map"], 512);
    assert!(report["camera"]["position"].is_array(), "{report}");
    let line: Vec<&str> = report["command_line"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(line.ends_with(&with_out), "{line:?}");

    let scene = first.join("scene.toml");
    assert_succeeded(&meadow(
        &[
            "render",
            "--scene",
            scene.to_str().unwrap(),
            "--out",
            again.to_str().unwrap(),
        ],
        &[],
    ));
    for name in ["frame_0000.png", "frame_0001.png"] {
        let a = std::fs::read(first.join(name)).unwrap();
        let b = std::fs::read(again.join(name)).unwrap();
        assert!(a == b, "{name} differs when rendered again from scene.toml");
    }
    let again_report = read_json(&again.join("report.json"));
    for key in [
        "blades",
        "seed",
        "width",
        "height",
        "msaa_requested",
        "view",
        "animation",
        "shadow_map",
    ] {
        assert_eq!(report[key], again_report[key], "{key}");
    }
    let _ = std::fs::remove_dir_all(&first);
    let _ = std::fs::remove_dir_all(&again);
}

/// A render into a folder an earlier render used replaces exactly that
/// run's files (frames, GIF, report, scene), as its manifest lists them,
/// and leaves anything else there alone, whatever its name; a refused run
/// changes nothing.
#[test]
fn a_reused_output_folder_never_mixes_two_runs() {
    let out = temp_out("reused");
    let out_s = out.to_str().unwrap();
    let render = |frames: &str, more: &[&str]| {
        let mut args = vec![
            "render",
            "--scene",
            "fig10-few-bunches",
            "--shadow-map",
            "0",
            "--width",
            "64",
            "--height",
            "36",
            "--fps",
            "10",
            "--frames",
            frames,
            "--out",
            out_s,
        ];
        args.extend(more);
        meadow(&args, &[])
    };
    assert_succeeded(&render("6", &[]));
    // The user's own files, two of them with a frame's name.
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    std::fs::write(out.join("frame_9999.png"), "mine").unwrap();
    std::fs::write(out.join("frame_12345.png"), "mine").unwrap();
    let six = files_in(&out);
    assert_eq!(six.len(), 6 + 3 + 3, "{six:?}");
    // A refused run leaves everything as it was.
    let refused = meadow(&["render", "--msaa", "3", "--out", out_s], &[]);
    assert!(!refused.status.success());
    assert_eq!(files_in(&out), six);
    assert_succeeded(&render("2", &[]));
    let theirs = ["frame_12345.png", "frame_9999.png", "notes.txt"];
    let with_theirs = |ours: &[&str]| {
        let mut all: Vec<String> = ours.iter().chain(&theirs).map(|s| s.to_string()).collect();
        all.sort();
        all
    };
    assert_eq!(
        files_in(&out),
        with_theirs(&[
            "animation.gif",
            "frame_0000.png",
            "frame_0001.png",
            "report.json",
            "scene.toml"
        ])
    );
    assert_succeeded(&render("1", &[]));
    let one = with_theirs(&["frame_0000.png", "report.json", "scene.toml"]);
    assert_eq!(files_in(&out), one);
    for name in theirs {
        assert_eq!(std::fs::read_to_string(out.join(name)).unwrap(), "mine");
    }

    // An output changed since meadow wrote it: refused before the work,
    // naming it and the fix; nothing removed.
    std::fs::write(out.join("frame_0000.png"), "edited").unwrap();
    let refused = render("1", &[]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success());
    assert!(
        stderr.contains("frame_0000.png changed since meadow wrote it")
            && stderr.contains("--overwrite"),
        "{stderr}"
    );
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert_eq!(files_in(&out), one);
    // --overwrite replaces it on purpose; the user's files still stay.
    assert_succeeded(&render("1", &["--overwrite"]));
    assert_eq!(files_in(&out), one);
    assert_ne!(
        std::fs::read(out.join("frame_0000.png")).unwrap(),
        b"edited"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// A folder holding a file of a name a command would write, which no
/// meadow run wrote there: refused before any work, the file untouched,
/// for every command that writes into --out.
#[test]
fn a_file_meadow_did_not_write_is_never_written_over() {
    for (command, name) in [
        ("render", "frame_0000.png"),
        ("render", "report.json"),
        ("wind", "wind_report.json"),
        ("trace", "space_time.svg"),
        ("bench", "bench.svg"),
        ("bench-grass", "grass_bench.json"),
        ("reproduce", "index.html"),
    ] {
        let out = temp_out(&format!("foreign-{command}"));
        std::fs::create_dir_all(&out).unwrap();
        std::fs::write(out.join(name), "mine").unwrap();
        let result = meadow(&[command, "--out", out.to_str().unwrap()], &[]);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(!result.status.success(), "{command}");
        assert!(
            stderr.contains(&format!("{name} is not from an earlier meadow run"))
                && stderr.contains("--overwrite"),
            "{command}: {stderr}"
        );
        assert_eq!(stderr.trim_end().lines().count(), 1, "{command}: {stderr}");
        assert_eq!(files_in(&out), [name], "{command}");
        assert_eq!(std::fs::read_to_string(out.join(name)).unwrap(), "mine");
        let _ = std::fs::remove_dir_all(&out);
    }
}

#[test]
fn devices_lists_at_least_one_qualifying_device() {
    let result = meadow(&["devices"], &[]);
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert_succeeded(&result);
    assert!(stdout.contains("qualifies"), "{stdout}");
}

#[test]
fn bench_grass_times_small_counts_and_refuses_bad_ones() {
    assert_refused(
        &["bench-grass", "--blades", "1k,zero"],
        &[],
        "blade count \"zero\" is not a count",
    );
    assert_refused(
        &["bench-grass", "--blades", "1k", "--colliders", "0,200"],
        &[],
        "a step simulates at most 128 colliders",
    );
    let out = temp_out("bench-grass");
    let result = meadow(
        &[
            "bench-grass",
            "--blades",
            "1k,2k",
            "--colliders",
            "0,3",
            "--steps",
            "3",
            "--warmup",
            "1",
            "--validation",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert_succeeded(&result);
    let bench = read_json(&out.join("grass_bench.json"));
    assert_eq!(bench["validation"]["errors"], 0);
    let rows = bench["rows"].as_array().unwrap();
    // Each count without and with 3 balls; each row's cost over the
    // collider-free row of its count.
    assert_eq!(rows.len(), 4);
    for (row, (blades, colliders)) in rows
        .iter()
        .zip([(1000, 0), (1000, 3), (2000, 0), (2000, 3)])
    {
        assert_eq!(row["blades"], blades);
        assert_eq!(row["colliders"], colliders);
        if let Some(ms) = row["step_ms_median"].as_f64() {
            let free = rows
                .iter()
                .find(|r| r["blades"] == blades && r["colliders"] == 0)
                .unwrap();
            let over = row["over_collider_free"].as_f64().unwrap();
            let expect = ms / free["step_ms_median"].as_f64().unwrap();
            assert!((over - expect).abs() <= 1e-9 * expect, "{row}");
        }
        assert_eq!(row["steps"], 3);
        assert!(row["substeps"].as_u64().unwrap() >= 1);
        // Timestamps exist on lavapipe; where they do, times are positive.
        if let Some(ms) = row["step_ms_median"].as_f64() {
            assert!(ms > 0.0 && ms.is_finite(), "{row}");
            assert!(row["step_ms_p95"].as_f64().unwrap() >= ms);
        }
        assert!(row["paper_ms"].is_null(), "the paper has no 1k figure");
        // Blades stepped with the contact: none without colliders; with
        // 3 balls over the field, some and not all.
        let touching = row["touching"].as_u64().unwrap();
        if colliders == 0 {
            assert_eq!(touching, 0, "{row}");
        } else {
            assert!(touching > 0 && touching < blades as u64, "{row}");
        }
        // The memory floor: each blade's rest shape and slot index read,
        // state read and written, four control points written, at the copy
        // bandwidth measured in the same run.
        use std::mem::size_of;
        let per_blade = size_of::<meadow::model::grass::GrassBlade>()
            + size_of::<u32>()
            + 2 * size_of::<meadow::model::grass::GrassState>()
            + 4 * size_of::<meadow::model::BladeVertex>();
        assert_eq!(row["bytes_per_step"], (blades * per_blade) as u64, "{row}");
        if let Some(gb_per_s) = bench["copy_bandwidth"]["gb_per_s"].as_f64() {
            assert!(gb_per_s > 0.1 && gb_per_s < 100_000.0, "{gb_per_s} GB/s");
            let floor = row["floor_ms"].as_f64().unwrap();
            let expect = (blades * per_blade) as f64 / (gb_per_s * 1e9) * 1e3;
            assert!(
                (floor - expect).abs() <= 1e-9 * expect.max(1.0),
                "{floor} vs {expect}"
            );
            let ms = row["step_ms_median"].as_f64().unwrap();
            let over = row["over_floor"].as_f64().unwrap();
            assert!((over - ms / floor).abs() <= 1e-9 * over, "{over}");
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn work_over_the_device_memory_budget_is_refused_before_allocating() {
    // The paper's 60x20x60 wind grid needs about 3.9 MiB (with the canopy
    // buffer of two-way coupling).
    assert_refused(
        &["wind", "--scene", "fig10-few-bunches", "--gpu-memory-mib", "1"],
        &[],
        "the 60x20x60 wind grid needs 3.9 MiB of GPU memory, more than the --gpu-memory-mib budget (1.0 MiB)",
    );
    // Ten million blades need about 2 GiB of grass buffers.
    assert_refused(
        &[
            "render",
            "--scene",
            "table1",
            "--blades",
            "10000000",
            "--gpu-memory-mib",
            "256",
        ],
        &[],
        "10000000 blades at 1280x720 with 8x MSAA needs",
    );
}

/// SIGTERM (what kill, schedulers and containers send) stops a render
/// while it is still simulating toward its first frame, within seconds:
/// exit 143, a report saying how far it got, no temporary file left.
#[test]
fn sigterm_while_simulating_stops_within_seconds_and_reports() {
    let out = temp_out("sigterm");
    let mut child = spawn_meadow(&[
        "render",
        "--scene",
        "fig10-few-bunches",
        "--start",
        "120",
        "--frames",
        "3",
        "--width",
        "96",
        "--height",
        "54",
        "--shadow-map",
        "0",
        "--out",
        out.to_str().unwrap(),
    ]);
    // 7,200 steps to the first frame: minutes of simulation on lavapipe.
    std::thread::sleep(std::time::Duration::from_secs(4));
    assert!(child.try_wait().unwrap().is_none(), "meadow ended early");
    let sent_at = std::time::Instant::now();
    let sent = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let result = child.wait_with_output().unwrap();
    let took = sent_at.elapsed();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(143), "{stderr}");
    assert!(stderr.contains("stopping (SIGTERM)"), "{stderr}");
    assert!(took.as_secs_f64() < 15.0, "took {took:?} to stop");
    let report = read_json(&out.join("report.json"));
    assert_eq!(report["interrupted"], true);
    assert_eq!(report["frames"], serde_json::json!([]));
    let steps = report["sim_steps"].as_u64().unwrap();
    assert!(steps > 0 && steps < 7200, "{steps} steps");
    assert_eq!(files_in(&out), ["report.json", "scene.toml"]);
    let _ = std::fs::remove_dir_all(&out);
}

/// Both cores kept busy by spinning threads until dropped: a machine
/// doing other work beside meadow.
struct BusyCores(Arc<AtomicBool>, Vec<std::thread::JoinHandle<()>>);

impl BusyCores {
    fn start(threads: usize) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let spinners = (0..threads)
            .map(|_| {
                let stop = stop.clone();
                std::thread::spawn(move || {
                    let mut x = 0u64;
                    while !stop.load(Ordering::Relaxed) {
                        x = std::hint::black_box(
                            x.wrapping_mul(6364136223846793005).wrapping_add(1),
                        );
                    }
                })
            })
            .collect();
        Self(stop, spinners)
    }
}

impl Drop for BusyCores {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
        for spinner in self.1.drain(..) {
            let _ = spinner.join();
        }
    }
}

/// Ctrl-C stops a render within about a second on a busy machine, where
/// it comes: while simulating toward a frame far ahead, and among frames
/// 30 steps apart. Table 1's wind grid (60 x 20 x 60) takes about 0.4 s
/// a step on lavapipe with the cores loaded: a fixed batch of 8 steps
/// per submission waited 3.2 s; the batches are paced to the machine now
/// (`StepPace`), and a frame's steps, shadow and colour are submitted
/// apart, a stop asked between them. The colour pass itself is not cut:
/// at 480 x 270 it is short; at 1280 x 720 with 8x MSAA a loaded lavapipe
/// takes up to 1.9 s over it (docs/reliability.md).
#[test]
fn a_stop_under_load_takes_about_a_second_wherever_it_comes() {
    let _busy = BusyCores::start(2);
    for (name, when, extra) in [
        ("ahead", 6, &["--start", "60", "--frames", "2"][..]),
        ("between", 10, &["--fps", "2", "--frames", "60"][..]),
    ] {
        let out = temp_out(&format!("stop-under-load-{name}"));
        let mut args = vec!["render", "--scene", "table1", "--blades", "20000"];
        args.extend([
            "--width",
            "480",
            "--height",
            "270",
            "--out",
            out.to_str().unwrap(),
        ]);
        args.extend(extra);
        let mut child = spawn_meadow(&args);
        std::thread::sleep(std::time::Duration::from_secs(when));
        assert!(
            child.try_wait().unwrap().is_none(),
            "{name}: meadow ended early"
        );
        let sent_at = std::time::Instant::now();
        send_sigint(&child);
        let result = child.wait_with_output().unwrap();
        let took = sent_at.elapsed().as_secs_f64();
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert_eq!(result.status.code(), Some(130), "{name}: {stderr}");
        eprintln!("{name}: stopped {took:.2} s after SIGINT under load");
        assert!(took < 1.5, "{name}: took {took:.2} s to stop under load");
        let report = read_json(&out.join("report.json"));
        assert_eq!(report["interrupted"], true, "{name}");
        let _ = std::fs::remove_dir_all(&out);
    }
}

#[test]
fn an_interrupted_render_leaves_only_complete_files_and_says_how_far_it_got() {
    let out = temp_out("interrupted");
    // A few frames, then Ctrl-C (SIGINT) mid-run.
    let result = interrupted_render(&out, &[]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("interrupted after"), "{stderr}");

    let report = read_json(&out.join("report.json"));
    assert_eq!(report["interrupted"], true);
    assert_eq!(report["frames_planned"], 2000);
    let listed: Vec<String> = report["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    assert!(listed.len() >= 4 && listed.len() < 2000, "{}", listed.len());
    // On disk: exactly the listed frames, the GIF, the report and the scene
    // as rendered, all complete.
    let on_disk = files_in(&out);
    let mut expected = listed.clone();
    expected.extend(["animation.gif", "report.json", "scene.toml"].map(String::from));
    expected.sort();
    assert_eq!(on_disk, expected);
    for name in &listed {
        let img = image::open(out.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((img.width(), img.height()), (160, 90));
    }
    use image::AnimationDecoder;
    let gif = std::io::BufReader::new(std::fs::File::open(out.join("animation.gif")).unwrap());
    let frames = image::codecs::gif::GifDecoder::new(gif)
        .unwrap()
        .into_frames()
        .collect_frames()
        .expect("the GIF decodes");
    assert_eq!(frames.len(), listed.len());
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn an_output_directory_that_cannot_be_made_is_one_line_and_no_file() {
    // The tests run as root, which permissions do not stop: a path under a
    // regular file cannot be a directory for anyone.
    let blocker = temp_out("blocker");
    std::fs::write(&blocker, b"not a directory").unwrap();
    let out = blocker.join("frames");
    for cmd in ["render", "wind", "bench", "reproduce"] {
        let result = meadow(&[cmd, "--out", out.to_str().unwrap()], &[]);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(!result.status.success(), "{cmd}");
        assert_eq!(stderr.lines().count(), 1, "{cmd}: {stderr}");
        assert!(
            stderr.contains("output directory") && stderr.contains("Not a directory"),
            "{cmd}: {stderr}"
        );
        // The cause is said once.
        assert_eq!(stderr.matches("os error").count(), 1, "{cmd}: {stderr}");
    }
    assert_eq!(std::fs::read(&blocker).unwrap(), b"not a directory");
    let _ = std::fs::remove_file(&blocker);
}

/// SIGTERM stops `meadow trace` between samples: exit 143, blades.csv and
/// trace.json complete and saying how far it got, no temporary file left.
#[test]
fn sigterm_stops_a_trace_with_complete_files() {
    let out = temp_out("trace-sigterm");
    let mut child = spawn_meadow_to(
        &[
            "trace",
            "--scene",
            "fig10-few-bunches",
            "--seconds",
            "600",
            "--every",
            "30",
            "--blades",
            "20",
            "--out",
            out.to_str().unwrap(),
        ],
        std::process::Stdio::piped(),
    );
    // 36,000 steps: far more than the seconds before the signal.
    std::thread::sleep(std::time::Duration::from_secs(6));
    assert!(child.try_wait().unwrap().is_none(), "meadow ended early");
    let sent = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let result = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(143), "{stderr}");
    let report = read_json(&out.join("trace.json"));
    assert_eq!(report["interrupted"], true);
    let samples = report["samples"].as_u64().unwrap();
    assert!((1..1201).contains(&samples), "{samples} samples");
    // The figures are what was done, the plan beside them.
    let steps = report["steps"].as_u64().unwrap();
    assert_eq!(steps, 30 * (samples - 1), "{report}");
    let seconds = report["seconds"].as_f64().unwrap();
    let dt = report["dt"].as_f64().unwrap();
    // dt is an f32 written to shortest digits: equal to about 1e-7.
    assert!(
        (seconds - steps as f64 * dt).abs() <= 1e-6 * seconds,
        "{report}"
    );
    assert_eq!(report["seconds_planned"], 600.0);
    assert_eq!(report["steps_planned"], 36_000);
    let csv = std::fs::read_to_string(out.join("blades.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("time_s,blade,root_x,root_z,tip_x,tip_y,tip_z,swing,bend,twist")
    );
    assert_eq!(
        lines.count() as u64,
        20 * samples,
        "one row per blade per sample"
    );
    // The space-time diagram needs two samples or more, the plan view
    // three seconds of them, the spectrum eight: each is written when the
    // report names it.
    assert_eq!(report["space_time"].is_string(), samples > 1, "{report}");
    // (The last sample is at `seconds`.)
    assert_eq!(report["plan_view"].is_string(), seconds >= 2.0, "{report}");
    assert_eq!(report["spectrum"].is_string(), samples >= 8, "{report}");
    let mut expected = vec!["blades.csv", "trace.json"];
    for picture in ["space_time", "plan_view", "spectrum"] {
        if let Some(name) = report[picture].as_str() {
            expected.push(name);
        }
    }
    expected.sort();
    assert_eq!(files_in(&out), expected);
    // The summary names every file written.
    let stdout = String::from_utf8_lossy(&result.stdout);
    let wrote = stdout
        .lines()
        .find(|l| l.starts_with("wrote "))
        .unwrap_or_else(|| panic!("no summary of the files: {stdout}"));
    for name in expected {
        assert!(wrote.contains(name), "{wrote} leaves out {name}");
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// A scene over a ridge, written beside `extra` files in a fresh folder;
/// `ground` is the [ground] table's body.
fn terrain_scene(name: &str, ground: &str, inflow: &str) -> std::path::PathBuf {
    let dir = temp_out(name);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(
        &path,
        format!(
            r#"name = "{name}"
seed = 1
[camera]
position = [0.0, 3.0, 6.0]
target = [0.0, 0.0, 0.0]
fov_y = 45.0
[[grass.meadow]]
center = [0.0, 0.0]
size = [4.0, 4.0]
count = 200
[ground]
{ground}
[wind]
cells = [20, 12, 20]
height = 2.0
[wind.inflow]
{inflow}
"#
        ),
    )
    .unwrap();
    path
}

/// `meadow wind` writes the field for analysis: wind_field.npy, float32
/// (nx, ny, nz, 3) at the cell centres, NaN exactly in the cells under the
/// ground, on the grid wind_report.json's `grid` gives; the grid reaches
/// from the lowest ground to wind.height above the highest.
#[test]
fn wind_writes_its_field_with_nan_under_the_ground() {
    let ridge =
        "[[ground.ridge]]\ncenter = [0.0, 0.0]\nheight = 1.0\nhalf_width = 1.0\nheading = 90.0";
    let scene = terrain_scene("wind-field", ridge, "speed = 2.0\nheading = 30.0");
    let out = temp_out("wind-field-out");
    let result = meadow(
        &[
            "wind",
            "--scene",
            scene.to_str().unwrap(),
            "--steps",
            "5",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert_succeeded(&result);
    let report = read_json(&out.join("wind_report.json"));
    let grid = &report["grid"];
    let f = |v: &serde_json::Value| v.as_f64().unwrap() as f32;
    let origin: Vec<f32> = grid["origin"].as_array().unwrap().iter().map(f).collect();
    let cell: Vec<f32> = grid["cell_size"]
        .as_array()
        .unwrap()
        .iter()
        .map(f)
        .collect();
    let cells: Vec<usize> = grid["cells"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap() as usize)
        .collect();
    assert_eq!(cells, [20, 12, 20]);
    // The highest ground is the crest, 1 m: 2 m of air above it.
    let top = origin[1] + cell[1] * 12.0;
    assert!((top - 3.0).abs() < 1e-3, "grid top {top}");
    let bytes = std::fs::read(out.join("wind_field.npy")).unwrap();
    assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
    let len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = std::str::from_utf8(&bytes[10..10 + len]).unwrap();
    assert!(
        header.contains("'descr': '<f4'") && header.contains("'shape': (20, 12, 20, 3)"),
        "{header}"
    );
    let values: Vec<f32> = bytes[10 + len..]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(values.len(), 20 * 12 * 20 * 3);
    let (mut under, mut moving) = (0, 0);
    for i in 0..20 {
        for j in 0..12 {
            for k in 0..20 {
                let at = 3 * (k + 20 * (j + 12 * i));
                let centre = |a: usize, n: usize| origin[a] + (n as f32 + 0.5) * cell[a];
                let ground = 1.0 / (1.0 + centre(0, i).powi(2));
                let nan = values[at].is_nan();
                assert_eq!(nan, centre(1, j) < ground, "cell ({i}, {j}, {k})");
                assert_eq!(nan, values[at + 1].is_nan() && values[at + 2].is_nan());
                under += nan as u32;
                moving += (!nan && values[at] > 0.5) as u32;
            }
        }
    }
    assert!(
        under > 100 && moving > 1000,
        "{under} under the ground, {moving} moving"
    );
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(scene.parent().unwrap());
}

/// Bad terrain and headings: one line naming the field and the fix, exit
/// 1, nothing written.
#[test]
fn bad_terrain_and_headings_are_refused_in_one_line() {
    let png = |name: &str, bytes: &[u8]| (name.to_string(), bytes.to_vec());
    let grey = {
        let mut b = Vec::new();
        image::codecs::png::PngEncoder::new(&mut b)
            .write_image(&[0u8; 16], 4, 4, image::ExtendedColorType::L8)
            .unwrap();
        b
    };
    let colour = {
        let mut b = Vec::new();
        image::codecs::png::PngEncoder::new(&mut b)
            .write_image(&[0u8; 48], 4, 4, image::ExtendedColorType::Rgb8)
            .unwrap();
        b
    };
    let white = {
        let mut b = Vec::new();
        image::codecs::png::PngEncoder::new(&mut b)
            .write_image(&[255u8; 16], 4, 4, image::ExtendedColorType::L8)
            .unwrap();
        b
    };
    let mut cut = grey.clone();
    cut.truncate(grey.len() - 12);
    // [ground] body, [wind.inflow] body, a file beside the scene, the refusal.
    type Case<'a> = (&'a str, &'a str, Option<(String, Vec<u8>)>, &'a str);
    let cases: Vec<Case> =
        vec![
        (
            "height_map = \"missing.png\"\nextent = [8.0, 8.0]",
            "speed = 2.0",
            None,
            "ground.height_map: ",
        ),
        (
            "height_map = \"c.png\"\nextent = [8.0, 8.0]",
            "speed = 2.0",
            Some(png("c.png", &colour)),
            "is Rgb8, not grey",
        ),
        (
            "height_map = \"t.png\"\nextent = [8.0, 8.0]",
            "speed = 2.0",
            Some(png("t.png", &cut)),
            "not a readable PNG",
        ),
        (
            "height_map = \"g.png\"",
            "speed = 2.0",
            Some(png("g.png", &grey)),
            "ground.extent: is missing",
        ),
        (
            "[[ground.hill]]\ncenter = [0.0, 0.0]\nheight = 1.0\nhalf_width = 0.0",
            "speed = 2.0",
            None,
            "ground.hill[0].half_width",
        ),
        (
            "[[ground.ridge]]\ncenter = [0.0, 0.0]\nheight = 1.0\nhalf_width = 1.0\nheading = nan",
            "speed = 2.0",
            None,
            "ground.ridge[0].heading: NaN is not allowed",
        ),
        ("", "speed = 2.0\nheading = inf", None, "wind.inflow.heading: inf is not allowed"),
        (
            // A plateau 4 m high under the camera at y = 3: the height
            // map's ground, checked once the map is read.
            "height_map = \"w.png\"\nextent = [16.0, 16.0]\nvertical_scale = 4.0",
            "speed = 2.0",
            Some(png("w.png", &white)),
            "camera.position: is 1.00 m under the ground, whose surface at x 0.0, z 6.0 is at y 4.00",
        ),
        (
            // 50 m of hill under 2 m of air in 12 cells: no cell of air
            // over it (narrow enough to leave the camera 6 m away clear).
            "[[ground.hill]]\ncenter = [0.0, 0.0]\nheight = 50.0\nhalf_width = 1.0",
            "speed = 2.0",
            None,
            "leaves less than one wind cell",
        ),
    ];
    for (n, (ground, inflow, file, fragment)) in cases.into_iter().enumerate() {
        let scene = terrain_scene(&format!("bad-terrain-{n}"), ground, inflow);
        if let Some((name, bytes)) = file {
            std::fs::write(scene.parent().unwrap().join(name), bytes).unwrap();
        }
        for command in ["render", "wind"] {
            assert_refused(
                &[command, "--scene", scene.to_str().unwrap()],
                &[],
                fragment,
            );
        }
        let _ = std::fs::remove_dir_all(scene.parent().unwrap());
    }
}

/// The scene a run saves beside its frames (scene.toml) names a user's
/// height map by its absolute path, so rendering that scene again finds
/// it: the same frame.
#[test]
fn a_saved_scene_finds_its_height_map_again() {
    use image::ImageEncoder;
    let heights: Vec<u8> = (0..64).map(|i| (i * 4) as u8).collect();
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(&heights, 8, 8, image::ExtendedColorType::L8)
        .unwrap();
    let scene = terrain_scene(
        "saved-height-map",
        "height_map = \"slope.png\"\nextent = [8.0, 8.0]\nvertical_scale = 0.5",
        "speed = 2.0",
    );
    std::fs::write(scene.parent().unwrap().join("slope.png"), png).unwrap();
    let (first, again) = (
        temp_out("saved-height-map-1"),
        temp_out("saved-height-map-2"),
    );
    let render = |scene: &std::path::Path, out: &std::path::Path| {
        let result = meadow(
            &[
                "render",
                "--scene",
                scene.to_str().unwrap(),
                "--frames",
                "1",
                "--width",
                "96",
                "--height",
                "64",
                "--shadow-map",
                "256",
                "--no-gif",
                "--out",
                out.to_str().unwrap(),
            ],
            &[],
        );
        assert!(
            result.status.success(),
            "{}",
            String::from_utf8_lossy(&result.stderr)
        );
    };
    render(&scene, &first);
    let saved = std::fs::read_to_string(first.join("scene.toml")).unwrap();
    let named = scene.parent().unwrap().join("slope.png");
    assert!(
        saved.contains(&format!("height_map = \"{}\"", named.display())),
        "{saved}"
    );
    render(&first.join("scene.toml"), &again);
    assert_eq!(
        std::fs::read(first.join("frame_0000.png")).unwrap(),
        std::fs::read(again.join("frame_0000.png")).unwrap()
    );
    for dir in [scene.parent().unwrap(), &first, &again] {
        let _ = std::fs::remove_dir_all(dir);
    }
}
