//! `meadow bench` at tiny counts, through the binary, with the validation
//! layer on: every field of bench.json, the Markdown table, an SVG that
//! parses as XML; the memory check before a huge count; the no-timestamp
//! path.

use crate::common;

use std::path::Path;

use common::binary::{meadow, read_json, temp_out};

fn tiny_bench(out: &Path, env: &[(&str, &str)]) -> serde_json::Value {
    let out_s = out.to_str().unwrap();
    let result = meadow(
        &[
            "bench",
            "--blades",
            "1k,2k",
            "--frames",
            "2",
            "--warmup",
            "1",
            "--width",
            "96",
            "--height",
            "64",
            // The wind on a small grid: the same kernels, and the rows'
            // and solvers' steps cost milliseconds, not the paper's
            // grid's fifth of a second each.
            "--cells",
            "12,6,12",
            "--validation",
            "--out",
            out_s,
        ],
        env,
    );
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    read_json(&out.join("bench.json"))
}

const PHASES: [&str; 8] = [
    "wind",
    "grass",
    "cull",
    "shadow",
    "colour",
    "grass_draw",
    "readback",
    "frame",
];

#[test]
fn tiny_bench_writes_every_field_a_table_and_an_svg() {
    let out = temp_out("tiny");
    let b = tiny_bench(&out, &[]);
    for key in [
        "scene",
        "device",
        "device_type",
        "driver",
        "width",
        "height",
        "msaa_requested",
        "msaa_used",
        "shadow_map",
        "wind_grid",
        "wind_solver",
        "jacobi_iterations",
        "v_cycles",
        "wind_solvers",
        "rows",
        "paper_table_1",
        "validation",
    ] {
        assert!(!b[key].is_null(), "bench.json lacks {key}");
    }
    assert_eq!(b["scene"], "table1");
    assert_eq!(b["wind_grid"], serde_json::json!([12, 6, 12]), "--cells");
    assert_eq!(b["validation"]["errors"], 0);
    assert_eq!(b["paper_table_1"].as_array().unwrap().len(), 4);
    // The wind step with each pressure solver, the scene's (multigrid) first.
    assert_eq!(b["wind_solver"], "multigrid");
    let solvers = b["wind_solvers"].as_array().unwrap();
    let names: Vec<_> = solvers
        .iter()
        .map(|s| s["solver"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["multigrid", "jacobi"]);
    for s in solvers {
        assert!(s["step_ms_median"].as_f64().unwrap() > 0.0, "{s}");
    }
    let rows = b["rows"].as_array().unwrap();
    // Two counts, each without and with LOD, each without and with culling.
    let keys: Vec<(u64, bool, bool)> = rows
        .iter()
        .map(|r| {
            (
                r["blades"].as_u64().unwrap(),
                r["lod"].as_bool().unwrap(),
                r["cull"].as_bool().unwrap(),
            )
        })
        .collect();
    let mut expected = Vec::new();
    for blades in [1000, 2000] {
        for lod in [false, true] {
            for cull in [false, true] {
                expected.push((blades, lod, cull));
            }
        }
    }
    assert_eq!(keys, expected);
    for r in rows {
        let what = format!(
            "{} blades, LOD {}, culling {}",
            r["blades"], r["lod"], r["cull"]
        );
        let cull = r["cull"] == true;
        // With culling the grass draws the blades in view; without, all.
        let drawn = if cull {
            let counts = &r["cull_counts"];
            assert_eq!(counts["blades"], r["blades"], "{what}");
            counts["in_view"].as_u64().unwrap()
        } else {
            assert!(r["cull_counts"].is_null(), "{what}");
            r["blades"].as_u64().unwrap()
        };
        assert_eq!(r["frames"], 2);
        assert_eq!(r["timing"]["frames"], 2);
        let frame = r["timing"]["gpu_ms"]["frame"]["median"].as_f64().unwrap();
        let untimed = &r["timing"]["phases_unavailable"];
        if b["device"].as_str().unwrap().contains("llvmpipe") {
            assert!(untimed["grass_draw"].is_string(), "{what}: {untimed}");
        }
        for p in PHASES {
            if p == "cull" && !cull {
                // Not recorded: exactly zero.
                assert_eq!(r["timing"]["gpu_ms"][p]["median"], 0.0, "{what}");
                continue;
            }
            if untimed[p].is_string() {
                assert!(
                    r["timing"]["gpu_ms"][p].is_null(),
                    "{what}: {p} untimed yet given"
                );
                continue;
            }
            let m = r["timing"]["gpu_ms"][p]["median"].as_f64().unwrap();
            assert!(
                m > 0.0 && m.is_finite() && m <= frame,
                "{what}: {p} {m} (frame {frame})"
            );
        }
        assert!(r["timing"]["fps"].as_f64().unwrap() > 0.0, "{what}");
        assert!(r["render_ms"]["median"].as_f64().unwrap() > 0.0, "{what}");
        let triangles = r["triangles"].as_u64().unwrap();
        assert_eq!(
            triangles,
            r["statistics"]["geometry_shader_primitives"]
                .as_u64()
                .unwrap()
        );
        let blades = r["blades"].as_u64().unwrap();
        if r["lod"] == false {
            // 20 segments of 2 triangles per blade drawn without LOD,
            // the tip's 1.
            assert_eq!(triangles, 39 * drawn, "{what}");
        } else {
            assert!(triangles < 39 * drawn && triangles >= 5 * drawn, "{what}");
        }
        let floor = &r["floor"];
        if cull {
            // The floor stands beside the draw of every blade.
            assert!(floor.is_null(), "{what}: {floor}");
            let why = r["floor_unavailable"].as_str().unwrap();
            assert!(why.contains("without culling"), "{what}: {why}");
            continue;
        }
        if untimed["grass_draw"].is_string() {
            // No ratio from a time the device cannot measure.
            assert!(floor.is_null(), "{what}: {floor}");
            let why = r["floor_unavailable"].as_str().unwrap();
            assert!(why.contains("grass draw cannot be timed"), "{what}: {why}");
            assert!(r["paper"].is_null(), "no paper row at {blades}");
            continue;
        }
        assert!(floor["draw_ms"]["median"].as_f64().unwrap() > 0.0, "{what}");
        assert!(floor["grass_over_floor"].as_f64().unwrap() > 0.0, "{what}");
        let floor_triangles = floor["triangles"].as_u64().unwrap() as f64;
        assert!(
            (floor_triangles - triangles as f64).abs() <= blades as f64,
            "{what}: the floor draws {floor_triangles} triangles for the grass's {triangles}"
        );
        assert!(r["paper"].is_null(), "no paper row at {blades}");
    }
    let md = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(
        md.contains("| blades | LOD | culling | wind ms | paper |"),
        "{md}"
    );
    assert!(md.contains("## Culling, off and on in this run"), "{md}");
    assert!(md.contains("grass / floor"), "{md}");
    assert!(md.contains("| multigrid | 7 V-cycles |"), "{md}");
    assert!(md.contains("| jacobi | 30 iterations |"), "{md}");
    // Four rows in each of the two timing tables, two in the culling one.
    assert_eq!(md.matches("\n| 1000 |").count(), 10, "{md}");
    let svg = std::fs::read_to_string(out.join("bench.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("bench.svg is XML");
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    // The data lines are the 2-px polylines (axes and ticks are 1 px).
    let lines = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline") && n.attribute("stroke-width") == Some("2"))
        .count();
    // Ours: five phases x two LOD settings; the paper's: four.
    assert_eq!(lines, 14);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn without_timestamps_the_bench_reports_unavailable_not_zero() {
    let out = temp_out("no-timestamps");
    let b = tiny_bench(&out, &[("MEADOW_PRETEND_MISSING", "timestamps")]);
    for r in b["rows"].as_array().unwrap() {
        assert!(r["timing"]["gpu_ms"].is_null(), "{}", r["timing"]);
        assert!(r["timing"]["gpu_unavailable"].is_string());
        assert!(r["floor"].is_null());
        let why = r["floor_unavailable"].as_str().unwrap();
        if r["cull"] == true {
            assert!(why.contains("without culling"), "{why}");
        } else {
            assert!(why.contains("timestamps"), "{why}");
        }
        assert!(
            r["timing"]["fps"].as_f64().unwrap() > 0.0,
            "wall clock still measured"
        );
    }
    let md = std::fs::read_to_string(out.join("bench.md")).unwrap();
    assert!(
        md.contains("n/a") && md.contains("GPU times unavailable"),
        "{md}"
    );
    let svg = std::fs::read_to_string(out.join("bench.svg")).unwrap();
    roxmltree::Document::parse(&svg).expect("bench.svg is XML");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_count_that_does_not_fit_is_refused_before_allocation() {
    let out = temp_out("huge");
    let result = meadow(
        &[
            "bench",
            "--blades",
            "10m",
            "--lod",
            "on",
            "--frames",
            "1",
            "--gpu-memory-mib",
            "256",
            "--out",
            out.to_str().unwrap(),
        ],
        &[],
    );
    assert!(!result.status.success());
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("10000000 blades") && stderr.contains("--gpu-memory-mib"),
        "{stderr}"
    );
    assert!(!out.join("bench.json").exists());
}

#[test]
fn bad_bench_arguments_are_refused_in_one_line() {
    for (args, fragment) in [
        (vec!["--blades", "0"], "blade count"),
        (vec!["--frames", "0"], "--frames 0"),
        (vec!["--width", "0"], "width"),
    ] {
        let out = temp_out("bad");
        let mut full = vec!["bench"];
        full.extend(args.iter().copied());
        let out_s = out.to_str().unwrap().to_string();
        full.extend(["--out", &out_s]);
        let result = meadow(&full, &[]);
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(!result.status.success(), "{args:?}");
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.contains(fragment), "{args:?}: {stderr}");
    }
}

/// bench, bench-grass and wind on a terminal (here a pseudo-terminal,
/// util-linux's `script`) say what they are doing: each step as it starts
/// (bench-grass printed nothing for minutes; bench for longer; wind for
/// the minute its default run takes on lavapipe).
#[test]
fn bench_bench_grass_and_wind_show_their_progress_on_a_terminal() {
    let out = temp_out("bench-terminal");
    let meadow = env!("CARGO_BIN_EXE_meadow");
    for (args, steps) in [
        (
            "bench-grass --blades 1k --steps 1 --warmup 0",
            &[
                "timing the grass step at 1000 blades",
                "measuring the copy bandwidth",
            ][..],
        ),
        (
            "bench --blades 1k --lod on --frames 1 --warmup 0 --width 64 --height 48",
            &[
                "timing the wind step with each pressure solver",
                "timing frames at 1000 blades, LOD on, culling off",
                "timing frames at 1000 blades, LOD on, culling on",
            ][..],
        ),
        (
            "wind --steps 4 --cells 12,6,12",
            &["/16 wind steps (the scene's, then each solver's and advection's)"][..],
        ),
    ] {
        let command = format!(
            "MEADOW_QUIET_VALIDATION=1 {meadow} {args} --out {}",
            out.display()
        );
        let result = std::process::Command::new("script")
            .args(["-qec", &command, "/dev/null"])
            .output()
            .expect("script (util-linux) runs");
        let terminal = String::from_utf8_lossy(&result.stdout);
        assert!(result.status.success(), "{args}: {terminal}");
        for said in steps {
            assert!(
                terminal.contains(said),
                "{args}: the terminal never showed {said:?}: {terminal}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// `--also-flat` runs each row again on the scene's ground made flat, the
/// same blades: bench.json marks each row's ground and bench.md sets the
/// two side by side; on a scene whose ground is flat it is refused in one
/// line, before any work.
#[test]
fn also_flat_sets_the_terrain_beside_flat_ground() {
    let out = temp_out("also-flat");
    let out_s = out.to_str().unwrap();
    let args = |scene: &'static str| {
        vec![
            "bench",
            "--scene",
            scene,
            "--also-flat",
            "--blades",
            "800",
            "--lod",
            "on",
            "--frames",
            "1",
            "--warmup",
            "0",
            "--width",
            "96",
            "--height",
            "64",
            "--shadow-map",
            "256",
            "--validation",
            "--out",
            out_s,
        ]
    };
    let refused = meadow(&args("table1"), &[]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(!refused.status.success());
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("--also-flat") && stderr.contains("hills"),
        "{stderr}"
    );
    assert!(!out.join("bench.json").exists());

    let result = meadow(&args("hills"), &[]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let b = read_json(&out.join("bench.json"));
    let rows = b["rows"].as_array().unwrap();
    let grounds: Vec<(bool, bool)> = rows
        .iter()
        .map(|r| {
            (
                r["cull"].as_bool().unwrap(),
                r["terrain"].as_bool().unwrap(),
            )
        })
        .collect();
    assert_eq!(
        grounds,
        [(false, true), (false, false), (true, true), (true, false)]
    );
    for r in rows {
        assert_eq!(r["blades"], 800);
    }
    let md = std::fs::read_to_string(out.join("bench.md")).unwrap();
    let table = md
        .split("## Terrain against flat ground in this run")
        .nth(1)
        .and_then(|rest| rest.split("\n## ").next())
        .expect("bench.md has the terrain table");
    let lines: Vec<&str> = table.lines().filter(|l| l.starts_with("| 800 |")).collect();
    assert_eq!(lines.len(), 2, "{table}");
    // Six phases, each flat, terrain and their ratio.
    assert_eq!(lines[0].matches('|').count(), 3 + 18 + 1, "{}", lines[0]);
    assert!(md.contains("| 800 (flat ground) |"));
    let _ = std::fs::remove_dir_all(&out);
}

/// `bench --against`: this binary against a copy of itself, two runs of
/// each, alternating. Every phase both timed is there with each run's
/// figure, and its ratios are the ones the raw figures give (the median
/// of new / old over the runs, the range around it). A missing binary and
/// one that is not meadow are refused in one line, nothing written, the
/// runs' temporary folder gone.
#[test]
fn bench_against_an_old_binary_gives_each_phase_as_a_ratio_of_runs() {
    let out = temp_out("bench-against");
    let old = out.with_extension("old-meadow");
    std::fs::copy(env!("CARGO_BIN_EXE_meadow"), &old).unwrap();
    let (old_s, out_s) = (old.to_str().unwrap(), out.to_str().unwrap());
    let bench = [
        "bench",
        "--blades",
        "1k",
        "--lod",
        "on",
        "--frames",
        "2",
        "--warmup",
        "0",
        "--width",
        "64",
        "--height",
        "48",
        "--shadow-map",
        "256",
        "--cells",
        "12,6,12",
        "--validation",
    ];
    let run = |against: &str, extra: &[&str]| {
        let mut args = bench.to_vec();
        args.extend(["--against", against, "--out", out_s]);
        args.extend(extra);
        let child = common::binary::spawn_meadow_to(&args, std::process::Stdio::piped());
        let pid = child.id();
        let result = child.wait_with_output().unwrap();
        let work = std::env::temp_dir().join(format!("meadow-against-{pid}"));
        assert!(!work.exists(), "{} left behind", work.display());
        result
    };
    let result = run(old_s, &["--runs", "2"]);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let stdout = String::from_utf8_lossy(&result.stdout);
    let a = read_json(&out.join("against.json"));
    assert_eq!(a["runs"], 2);
    assert_eq!(a["order"], serde_json::json!(["old", "new", "new", "old"]));
    let phases = a["phases"].as_array().unwrap();
    let named = |row: &str, phase: &str| {
        phases
            .iter()
            .find(|p| p["row"] == row && p["phase"] == phase)
            .unwrap_or_else(|| panic!("no {row} / {phase} in {phases:?}"))
    };
    named("wind step", "multigrid");
    named("wind step", "jacobi");
    for cull in ["off", "on"] {
        let row = format!("1000 blades, LOD on, culling {cull}");
        for phase in ["wind", "grass", "shadow", "colour", "frame", "wall frame"] {
            named(&row, phase);
        }
        assert!(stdout.contains(&format!("| {row} | colour |")), "{stdout}");
    }
    for p in phases {
        let ms = |key: &str| -> Vec<f64> {
            p[key]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect()
        };
        let (old_ms, new_ms) = (ms("old_ms"), ms("new_ms"));
        assert_eq!((old_ms.len(), new_ms.len()), (2, 2), "{p}");
        let mut ratios: Vec<f64> = old_ms
            .iter()
            .zip(&new_ms)
            .filter(|(o, _)| **o > 0.0)
            .map(|(o, n)| n / o)
            .collect();
        ratios.sort_by(f64::total_cmp);
        if ratios.is_empty() {
            assert!(p["ratio_median"].is_null(), "{p}");
            continue;
        }
        let expected = ratios.iter().sum::<f64>() / ratios.len() as f64; // 1 or 2 runs
        let close = |key: &str, want: f64| {
            let got = p[key].as_f64().unwrap();
            assert!(
                (got - want).abs() <= 1e-9 * want.abs().max(1.0),
                "{key}: {got} against {want}: {p}"
            );
        };
        close("ratio_median", expected);
        close("ratio_min", ratios[0]);
        close("ratio_max", ratios[ratios.len() - 1]);
        assert!(ratios.iter().all(|r| r.is_finite() && *r > 0.0), "{p}");
    }
    // Refused in one line, nothing written.
    let _ = std::fs::remove_dir_all(&out);
    for (against, says) in [
        ("/nonexistent/meadow", "no such file"),
        ("/bin/true", "wrote no bench.json"),
    ] {
        let result = run(against, &["--runs", "1"]);
        assert!(!result.status.success());
        let stderr = String::from_utf8_lossy(&result.stderr);
        let last = stderr.lines().last().unwrap_or("");
        assert!(
            last.starts_with("meadow: error: ") && last.contains(says),
            "{stderr}"
        );
        assert!(!out.join("against.json").exists());
    }
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_file(&old);
}
