//! `scripts/gpu-report --quick` on the default device, through the script
//! and the binary, so that the one command for every GPU figure cannot
//! rot: every part ran and holds figures, each command ran once under
//! validation with no error, the targets are each said (not measured at
//! these sizes), the Markdown has every table; and a report whose parts
//! fail still writes what it has and fails naming them.

use crate::common;

use std::path::Path;
use std::process::{Command, Output};

use common::binary::{read_json, temp_out};

fn gpu_report(out: &Path, work: &Path, extra: &[&str]) -> Output {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("scripts/gpu-report");
    Command::new(script)
        .args(["--quick", "--out", out.to_str().unwrap()])
        .args(["--work", work.to_str().unwrap()])
        .args(extra)
        .env("MEADOW_BIN", env!("CARGO_BIN_EXE_meadow"))
        .env("MEADOW_QUIET_VALIDATION", "1")
        .output()
        .expect("run scripts/gpu-report")
}

/// The one report file with this extension in `out`.
fn report_file(out: &Path, ext: &str) -> std::path::PathBuf {
    let found: Vec<_> = std::fs::read_dir(out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    assert_eq!(found.len(), 1, "{found:?}");
    found[0].clone()
}

fn number(v: &serde_json::Value, what: &str) -> f64 {
    v.as_f64()
        .unwrap_or_else(|| panic!("{what} is not a number: {v}"))
}

#[test]
fn the_quick_gpu_report_runs_every_part_and_validates_every_command() {
    let (out, work) = (temp_out("gpu-report"), temp_out("gpu-report-work"));
    let started = std::time::Instant::now();
    let result = gpu_report(&out, &work, &[]);
    let stdout = String::from_utf8_lossy(&result.stdout);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(result.status.success(), "{stdout}\n{stderr}");
    eprintln!(
        "scripts/gpu-report --quick took {:.0} s\n{stdout}",
        started.elapsed().as_secs_f64()
    );
    let json = report_file(&out, "json");
    let r = read_json(&json);
    assert_eq!(r["quick"], true);
    for key in [
        "device",
        "device_type",
        "driver",
        "api_version",
        "commit",
        "date",
    ] {
        assert!(
            r[key].as_str().is_some_and(|s| !s.is_empty()),
            "{key}: {}",
            r[key]
        );
    }
    let stem = json.file_stem().unwrap().to_str().unwrap();
    let device = r["device"].as_str().unwrap().to_lowercase();
    assert!(
        device.starts_with(stem.split('-').next().unwrap()),
        "{stem} for {device}"
    );

    // The frame: each row with and without culling and LOD, each phase
    // timed (lavapipe has timestamps).
    let rows = r["bench"]["ran"]["rows"].as_array().expect("bench ran");
    let mut seen: Vec<(bool, bool)> = rows
        .iter()
        .map(|row| (row["lod"] == true, row["cull"] == true))
        .collect();
    seen.sort();
    assert_eq!(
        seen,
        [(false, false), (false, true), (true, false), (true, true)]
    );
    for row in rows {
        let frame = number(&row["timing"]["gpu_ms"]["frame"]["median"], "frame ms");
        assert!(frame > 0.0, "{row}");
    }
    // The grass step beside its memory floor, and with colliders beside
    // the same count without.
    for row in r["grass"]["ran"]["rows"]
        .as_array()
        .expect("bench-grass ran")
    {
        assert!(number(&row["over_floor"], "over_floor") > 0.0, "{row}");
    }
    let colliders = r["colliders"]["ran"]["rows"]
        .as_array()
        .expect("colliders ran");
    assert!(colliders
        .iter()
        .any(|row| row["colliders"].as_u64() > Some(0)
            && number(&row["over_collider_free"], "over_collider_free") > 0.0));
    // The wind step, both solvers, both couplings.
    for part in ["wind", "wind_two_way"] {
        let solvers = r[part]["ran"]["solvers"].as_array().expect(part);
        assert_eq!(solvers.len(), 2, "{part}");
        for s in solvers {
            assert!(number(&s["step_ms_median"], "step ms") > 0.0, "{s}");
        }
    }
    assert_eq!(r["wind_two_way"]["ran"]["coupling"], "two-way");
    // Frames of prairie and roll.
    let frames: Vec<&str> = r["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["ran"]["scene"].as_str().expect("render ran"))
        .collect();
    assert_eq!(frames, ["prairie", "roll"]);
    // Each command once under validation, no error.
    let validated = r["validation"].as_array().unwrap();
    let commands: Vec<&str> = validated
        .iter()
        .map(|v| v["command"].as_str().unwrap().split(' ').next().unwrap())
        .collect();
    assert_eq!(
        commands,
        ["bench", "bench-grass", "wind", "wind", "render", "render"]
    );
    for v in validated {
        assert_eq!(v["outcome"]["ran"]["errors"], 0, "{v}");
    }
    // Every target said; none measured at --quick's sizes.
    let targets = r["targets"].as_array().unwrap();
    let names: Vec<&str> = targets
        .iter()
        .map(|t| t["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        [
            "frame_200k",
            "fps_1m",
            "wind_multigrid_ms",
            "grass_over_floor",
            "colliders_128"
        ]
    );
    for t in targets {
        assert!(t["met"].is_null() && t["measured"].is_null(), "{t}");
        assert!(!t["note"].as_str().unwrap().is_empty(), "{t}");
    }
    let md = std::fs::read_to_string(report_file(&out, "md")).unwrap();
    for heading in [
        "## Targets",
        "## The frame",
        "## The grass step and its memory floor",
        "## The grass step with colliders",
        "## The wind step",
        "## Frames of shipped scenes",
        "## Under validation",
        "--quick",
    ] {
        assert!(md.contains(heading), "{heading} missing:\n{md}");
    }
    // The commands' own outputs are in the work folder, not beside the
    // report.
    assert!(work.join("bench/bench.json").exists());
    assert!(work.join("frames-roll/frame_0001.png").exists());
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&work);
}

#[test]
fn a_report_whose_parts_fail_is_written_and_fails_naming_them() {
    let (out, work) = (
        temp_out("gpu-report-fails"),
        temp_out("gpu-report-fails-work"),
    );
    // 1 MiB of GPU memory: every part is refused before its work.
    let result = gpu_report(&out, &work, &["--gpu-memory-mib", "1"]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(1), "{stderr}");
    let last = stderr.lines().last().unwrap_or("");
    assert!(
        last.starts_with("meadow: error: ")
            && last.contains("part(s) failed")
            && last.contains("bench"),
        "{stderr}"
    );
    let r = read_json(&report_file(&out, "json"));
    let failed = r["bench"]["failed"].as_str().expect("bench failed");
    assert!(failed.contains("memory"), "{failed}");
    assert!(r["targets"][0]["met"].is_null());
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&work);
}
