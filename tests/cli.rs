//! The `meadow` binary: bad input gives one clear line and a non-zero exit
//! and leaves no frame behind; a good run writes the frame and the report.
//! The wind command's lines are in tests/cli_wind.rs, stopping a run in
//! tests/cli_signals.rs.

use crate::common;

use common::binary::{assert_refused, assert_succeeded, files_in, meadow, read_json, temp_out};

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
    assert!(stats["geometry_shader_primitives"].as_u64().unwrap() >= in_view * (2 * 3 - 1));
    let shadow = &report["shadow_pipeline_statistics"];
    assert_eq!(
        shadow["tessellation_control_patches"],
        counts["shadow_casters"]
    );
    let casters = counts["shadow_casters"].as_u64().unwrap();
    assert!(casters > 0);
    // One segment at least, the close shadow level (10) at most: a caster
    // is tessellated no finer than its size in the map needs.
    let segments = shadow["geometry_shader_invocations"].as_u64().unwrap();
    assert!(
        (casters..=10 * casters).contains(&segments),
        "{segments} for {casters}"
    );
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
            // Two wind steps, not 30: each row's wind is the same work
            // whatever its blades, and the rows check the grass.
            "--wind-warmup",
            "2",
            "--validation",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert_succeeded(&result);
    let bench = read_json(&out.join("grass_bench.json"));
    assert_eq!(bench["validation"]["errors"], 0);
    assert_eq!(bench["wind_warmup_steps"], 2);
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
    // The paper's 60x20x60 wind grid needs about 4.2 MiB (with the canopy
    // buffer of two-way coupling).
    assert_refused(
        &["wind", "--scene", "fig10-few-bunches", "--gpu-memory-mib", "1"],
        &[],
        "the 60x20x60 wind grid needs 4.2 MiB of GPU memory, more than the --gpu-memory-mib budget (1.0 MiB)",
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
