//! Faults, injected and real, through the `meadow` binary with validation
//! on: device memory running out at every allocation site in turn (injected,
//! MEADOW_INJECT_FAULT) and for real under an address-space limit; the
//! device lost at every submission in turn (injected); the disk filling up
//! while frames are written (a real, tiny tmpfs). Each must give one line
//! naming the cause, a non-zero exit, no validation error on the failure
//! path (every object destroyed), and only complete files on disk.

use crate::common;

use std::path::Path;
use std::process::{Command, Output};

use common::binary::{files_in, meadow, temp_out};

/// The most operations any command here makes; a loop past it means the
/// injected fault never fired.
const MAX_OPERATIONS: u64 = 400;

fn stderr_of(result: &Output) -> String {
    String::from_utf8_lossy(&result.stderr).into_owned()
}

/// A failure: exit status 1 (not a panic's 101 or an abort's 134), one
/// line, no panic, and validation had nothing to add.
fn assert_one_clean_line(what: &str, result: &Output) -> String {
    let stderr = stderr_of(result);
    assert_eq!(result.status.code(), Some(1), "{what}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{what}: {stderr}");
    assert!(stderr.starts_with("meadow: error: "), "{what}: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    assert!(
        !stderr.contains("validation reported"),
        "{what}: the failure path upset validation: {stderr}"
    );
    stderr
}

/// Nothing half-written: no temporary file, every image decodes, every
/// JSON parses.
fn assert_only_complete_files(what: &str, dir: &Path) {
    for name in files_in(dir) {
        let path = dir.join(&name);
        assert!(!name.contains(".partial"), "{what}: left {name}");
        if name.ends_with(".png") || name.ends_with(".gif") {
            image::open(&path).unwrap_or_else(|e| panic!("{what}: {name} is broken: {e}"));
        } else if name.ends_with(".json") {
            let bytes = std::fs::read(&path).unwrap();
            serde_json::from_slice::<serde_json::Value>(&bytes)
                .unwrap_or_else(|e| panic!("{what}: {name} is broken: {e}"));
        }
    }
}

/// Table 1's meadow on a small wind grid (for `bench`).
const SMALL_WIND_SCENE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/faults/small-wind.toml");

/// Small runs of each command that allocates device memory.
fn commands(out: &str) -> Vec<(&'static str, Vec<String>)> {
    let tiny = |args: &[&str]| -> Vec<String> {
        let mut v: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        v.extend(["--validation".into(), "--out".into(), out.into()]);
        v
    };
    vec![
        (
            "render",
            tiny(&[
                "render",
                "--scene",
                "fig10-few-bunches",
                "--width",
                "64",
                "--height",
                "48",
                "--shadow-map",
                "256",
                "--frames",
                "4",
            ]),
        ),
        // The wind grid small (the same buffers, each smaller): every run
        // up to the failing allocation then costs milliseconds of wind
        // step, not the paper's 60 x 20 x 60 grid's quarter second.
        (
            "wind",
            tiny(&[
                "wind",
                "--scene",
                "fig13-obstacles",
                "--steps",
                "2",
                "--cells",
                "12,6,12",
            ]),
        ),
        (
            "bench",
            tiny(&[
                "bench",
                "--scene",
                SMALL_WIND_SCENE,
                "--blades",
                "1k",
                "--lod",
                "on",
                "--frames",
                "1",
                "--warmup",
                "0",
                "--width",
                "64",
                "--height",
                "48",
                "--shadow-map",
                "256",
            ]),
        ),
        (
            "bench-grass",
            tiny(&[
                "bench-grass",
                "--blades",
                "1k",
                "--steps",
                "1",
                "--warmup",
                "0",
                "--wind-warmup",
                "1",
            ]),
        ),
    ]
}

/// Runs `args` with the fault `kind@N` for N = 1, 2, ... until a run
/// succeeds. Each failure must be one clean line saying the N-th operation
/// failed, with only complete files in `out`; `check` sees its stderr.
/// Returns how many runs failed.
fn each_failing_in_turn(
    kind: &str,
    operation: &str,
    args: &[&str],
    out: &Path,
    mut check: impl FnMut(&str, &str),
) -> u64 {
    for n in 1..=MAX_OPERATIONS {
        let _ = std::fs::remove_dir_all(out);
        let fault = format!("{kind}@{n}");
        let result = meadow(args, &[("MEADOW_INJECT_FAULT", &fault)]);
        if result.status.success() {
            return n - 1;
        }
        let what = format!("{} with {fault}", args[0]);
        let stderr = assert_one_clean_line(&what, &result);
        assert!(
            stderr.contains(&format!("(injected: {operation} {n})")),
            "{what}: {stderr}"
        );
        assert_only_complete_files(&what, out);
        check(&what, &stderr);
    }
    panic!("{}: {kind} never stopped failing", args[0]);
}

/// The device memory allocations one run of `args` makes, in order, as
/// the fault hook lists them (MEADOW_INJECT_FAULT=list): (N, what).
fn listed_allocations(args: &[&str]) -> Vec<(u64, String)> {
    let result = meadow(args, &[("MEADOW_INJECT_FAULT", "list")]);
    let stderr = stderr_of(&result);
    assert!(result.status.success(), "{}: {stderr}", args[0]);
    stderr
        .lines()
        .filter_map(|l| l.strip_prefix("meadow: fault hook: allocation "))
        .map(|l| {
            let (n, what) = l.split_once(": ").unwrap();
            (n.parse().unwrap(), what.to_string())
        })
        .collect()
}

/// Each device memory allocation site of command `name` (of `commands`)
/// failing in turn is one clean line naming it. A site is an allocation's
/// name: one made again under its name (the next bench row's frame, the
/// next solver's wind pass, another readback) is the same code on the same
/// path, so each name's first allocation fails, and the run's last one
/// (after everything else has run and been released). One test per
/// command, so that the harness runs them side by side.
fn every_allocation_of(name: &str) {
    let out = temp_out(&format!("oom-each-{name}"));
    let out_s = out.to_str().unwrap().to_string();
    let (_, args) = commands(&out_s)
        .into_iter()
        .find(|(n, _)| *n == name)
        .unwrap();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let listed = listed_allocations(&args);
    let numbered: Vec<u64> = listed.iter().map(|&(n, _)| n).collect();
    assert_eq!(numbered, (1..=listed.len() as u64).collect::<Vec<_>>());
    let last = listed.len() as u64;
    let mut names = std::collections::HashSet::new();
    let sites: Vec<&(u64, String)> = listed
        .iter()
        .filter(|(n, what)| names.insert(what.as_str()) || *n == last)
        .collect();
    for (n, site) in &sites {
        let _ = std::fs::remove_dir_all(&out);
        let fault = format!("out-of-device-memory@{n}");
        let result = meadow(&args, &[("MEADOW_INJECT_FAULT", &fault)]);
        let what = format!("{name} with {fault}");
        let stderr = assert_one_clean_line(&what, &result);
        assert!(
            stderr.contains(&format!(
                "out of GPU memory while creating {site} (injected: allocation {n})"
            )),
            "{what}: {stderr}"
        );
        assert_only_complete_files(&what, &out);
    }
    // Every render target, texture, wind and grass buffer and staging
    // copy is one allocation; fewer would mean the hook is dead.
    assert!(
        sites.len() >= 10,
        "{name}: only {} allocation sites",
        sites.len()
    );
    eprintln!(
        "{name}: {} allocations at {} sites, each site failing cleanly in turn",
        listed.len(),
        sites.len()
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn every_device_memory_allocation_of_render_failing_in_turn_is_one_clean_line() {
    every_allocation_of("render");
}

#[test]
fn every_device_memory_allocation_of_wind_failing_in_turn_is_one_clean_line() {
    every_allocation_of("wind");
}

#[test]
fn every_device_memory_allocation_of_bench_failing_in_turn_is_one_clean_line() {
    every_allocation_of("bench");
}

#[test]
fn every_device_memory_allocation_of_bench_grass_failing_in_turn_is_one_clean_line() {
    every_allocation_of("bench-grass");
}

#[test]
fn a_lost_device_is_named_with_its_frame_and_the_frames_before_stay_valid() {
    let out = temp_out("device-lost");
    let out_s = out.to_str().unwrap().to_string();
    let (_, args) = commands(&out_s).swap_remove(0);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let mut lost_frames = Vec::new();
    each_failing_in_turn("device-lost", "submission", &args, &out, |what, e| {
        assert!(e.contains("lost (VK_ERROR_DEVICE_LOST)"), "{what}: {e}");
        // Lost while rendering frame k: frames 0..k are on disk, whole.
        let frame = e
            .split("during frame ")
            .nth(1)
            .map(|rest| rest.split(',').next().unwrap().parse::<u32>().unwrap());
        // Lost after the last frame (reading the counters back): all four
        // frames and the finished GIF.
        let after_last = e.contains("after the last frame (the frames are complete)");
        let written = if after_last { 4 } else { frame.unwrap_or(0) };
        let mut expected: Vec<String> = (0..written).map(|k| format!("frame_{k:04}.png")).collect();
        if after_last {
            expected.insert(0, "animation.gif".into());
        }
        assert_eq!(files_in(&out), expected, "{what}: {e}");
        if let Some(k) = frame {
            assert!(e.contains("(the frames before it are complete)"), "{e}");
            lost_frames.push(k);
        }
    });
    // A frame goes to the GPU in several submissions (steps ahead of it,
    // its own steps, its shadow, its colour): each loss names its frame,
    // in order, and every frame is lost at some submission.
    assert!(lost_frames.is_sorted(), "{lost_frames:?}");
    let mut frames = lost_frames.clone();
    frames.dedup();
    assert_eq!(
        frames,
        [0, 1, 2, 3],
        "a loss in each frame: {lost_frames:?}"
    );
    assert!(
        lost_frames.len() > 4,
        "each frame's submissions: {lost_frames:?}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// Beside the drawing (`--overlap on`, src/frame/ahead.rs) a frame's steps
/// and its drawing are submissions of their own, ordered by semaphores,
/// and the next frame's steps are in flight while a frame is read back:
/// the device lost at each submission in turn is one clean line, and
/// nothing in flight is left behind at teardown (validation would name
/// it). The bench's frames with the steps sent ahead are among them.
/// (Broken by hand, the command pool not waiting for its submission in
/// flight before it goes: it failed.)
#[test]
fn a_lost_device_beside_the_drawing_is_one_clean_line() {
    let out = temp_out("device-lost-overlap");
    let out_s = out.to_str().unwrap().to_string();
    let (_, mut args) = commands(&out_s)
        .into_iter()
        .find(|(n, _)| *n == "bench")
        .unwrap();
    let frames = args.iter().position(|a| a == "--frames").unwrap() + 1;
    args[frames] = "2".into();
    args.extend(["--overlap".into(), "on".into()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let mut beside = 0;
    let submissions = each_failing_in_turn("device-lost", "submission", &args, &out, |what, e| {
        assert!(e.contains("lost (VK_ERROR_DEVICE_LOST)"), "{what}: {e}");
        beside += u32::from(e.contains("simulating beside the drawing"));
    });
    // Each timed frame's steps, and the warm-up's, went beside the drawing.
    assert!(
        beside >= 2,
        "{beside} of {submissions} losses were the steps'"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// Runs the shell `script` in a private mount namespace (unshare, as root
/// or through a user namespace), with $MNT an empty folder to mount on,
/// $KEEP a folder outside the namespace to copy results to, and $MEADOW the
/// binary; the script writes meadow's exit status to $KEEP/rc and its
/// stderr to $KEEP/stderr, returned here, stderr checked to be one line.
fn in_private_mount(script: &str, mount: &Path, keep: &Path) -> (String, String) {
    let status = Command::new("unshare")
        .args(["-rm", "sh", "-c", script])
        .env("MNT", mount)
        .env("KEEP", keep)
        .env("MEADOW", env!("CARGO_BIN_EXE_meadow"))
        .status()
        .expect("unshare (util-linux) runs");
    assert!(
        status.success(),
        "could not mount a tmpfs in a private namespace ({status}); the test needs unshare -rm"
    );
    let rc = std::fs::read_to_string(keep.join("rc")).unwrap();
    let stderr = std::fs::read_to_string(keep.join("stderr")).unwrap();
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    (rc.trim().to_string(), stderr)
}

#[test]
fn a_disk_filling_up_while_frames_are_written_is_one_line_and_leaves_only_complete_frames() {
    // A private mount namespace (unshare, as root or through a user
    // namespace) with a 300 KiB tmpfs: room for a few 320x180 frames
    // (about 50 KiB each), and for the least 8 of them may take (28 KiB
    // each), so the check before the work lets it start. What meadow
    // leaves there is copied out before the namespace goes.
    let keep = temp_out("disk-full");
    std::fs::create_dir_all(keep.join("out")).unwrap();
    let mount = keep.join("mnt");
    std::fs::create_dir_all(&mount).unwrap();
    let script = r#"
        mount -t tmpfs -o size=300k meadow-full "$MNT" || exit 90
        MEADOW_QUIET_VALIDATION=1 "$MEADOW" render --scene fig10-few-bunches \
            --width 320 --height 180 --shadow-map 1024 --frames 8 --validation \
            --out "$MNT/out" 2>"$KEEP/stderr"
        echo $? >"$KEEP/rc"
        cp -a "$MNT/out/." "$KEEP/out/"
    "#;
    let (rc, stderr) = in_private_mount(script, &mount, &keep);
    assert_eq!(rc, "1", "{stderr}");
    assert!(
        stderr.contains("No space left on device") && stderr.contains("free some space"),
        "{stderr}"
    );
    assert!(!stderr.contains("validation reported"), "{stderr}");
    let out = keep.join("out");
    assert_only_complete_files("disk full", &out);
    let left = files_in(&out);
    // Some frames fitted, in order from the first, and not all of them.
    let expected: Vec<String> = (0..left.len())
        .map(|k| format!("frame_{k:04}.png"))
        .collect();
    assert!(!left.is_empty() && left.len() < 8, "{left:?}");
    assert_eq!(left, expected, "only whole frames, no GIF, no report");
    let _ = std::fs::remove_dir_all(&keep);
}

/// A folder without room for the least the frames will take is refused
/// before the work, in one line naming the folder, its free room and the
/// need: 12 frames of 320 x 180 take at least 337.5 KiB (an eighth of
/// their pixels' bytes each; they take about 50 KiB), and the 300 KiB
/// tmpfs holds fewer. Two simulated seconds come before the first frame:
/// without the check they ran, and the disk filled before the run's end
/// (at the GIF, after twelve frames of this later, calmer instant).
#[test]
fn a_folder_without_room_for_the_frames_is_refused_before_the_work() {
    let keep = temp_out("no-room");
    std::fs::create_dir_all(keep.join("out")).unwrap();
    let mount = keep.join("mnt");
    std::fs::create_dir_all(&mount).unwrap();
    let script = r#"
        mount -t tmpfs -o size=300k meadow-small "$MNT" || exit 90
        MEADOW_QUIET_VALIDATION=1 "$MEADOW" render --scene fig10-few-bunches \
            --width 320 --height 180 --shadow-map 1024 --frames 12 --start 2 \
            --validation --out "$MNT/out" 2>"$KEEP/stderr"
        echo $? >"$KEEP/rc"
        cp -a "$MNT/out/." "$KEEP/out/"
    "#;
    let (rc, stderr) = in_private_mount(script, &mount, &keep);
    assert_eq!(rc, "1", "{stderr}");
    assert!(
        stderr.contains("/out has 300.0 KiB free and 12 PNG frames of 320 x 180 would take at least about 337.5 KiB; free some space or pass --out a folder on another disk"),
        "{stderr}"
    );
    assert!(!stderr.contains("simulated"), "{stderr}");
    assert!(files_in(&keep.join("out")).is_empty());
    let _ = std::fs::remove_dir_all(&keep);
}

/// An `--out` folder that exists but cannot be written (here a read-only
/// file system, which stops root too) is refused before any work: the one
/// line names the folder, not the first frame it could not write, and the
/// folder is left as it was.
#[test]
fn an_output_folder_that_cannot_be_written_is_refused_before_the_work() {
    let keep = temp_out("read-only-out");
    let mount = keep.join("mnt");
    std::fs::create_dir_all(&mount).unwrap();
    // Two simulated seconds before the first frame: work that a check at
    // the first frame would come after.
    let script = r#"
        mount -t tmpfs -o size=64k meadow-ro "$MNT" || exit 90
        mkdir "$MNT/out" && echo mine >"$MNT/out/notes.txt" || exit 91
        mount -o remount,ro "$MNT" || exit 92
        MEADOW_QUIET_VALIDATION=1 "$MEADOW" render --scene fig10-few-bunches \
            --width 64 --height 48 --start 2 --validation \
            --out "$MNT/out" 2>"$KEEP/stderr"
        echo $? >"$KEEP/rc"
        ls -A "$MNT/out" >"$KEEP/left"
        MEADOW_QUIET_VALIDATION=1 "$MEADOW" render --scene fig10-few-bunches \
            --width 64 --height 48 --start 2 --frames 2 \
            --video "$MNT/out/run.mp4" --out "$KEEP/video-frames" 2>"$KEEP/video-stderr"
        echo $? >"$KEEP/video-rc"
    "#;
    let (rc, stderr) = in_private_mount(script, &mount, &keep);
    assert_eq!(rc, "1", "{stderr}");
    assert!(
        stderr.contains("output directory")
            && stderr.contains("pass --out a directory you can write")
            && stderr.contains("Read-only file system"),
        "{stderr}"
    );
    let left = std::fs::read_to_string(keep.join("left")).unwrap();
    assert_eq!(left.trim(), "notes.txt");
    // A --video in a folder that cannot be written: the same, before the
    // work (the frames' folder is writable).
    let rc = std::fs::read_to_string(keep.join("video-rc")).unwrap();
    let stderr = std::fs::read_to_string(keep.join("video-stderr")).unwrap();
    assert_eq!(rc.trim(), "1", "{stderr}");
    assert!(
        stderr.contains("folder of --video") && stderr.contains("Read-only file system"),
        "{stderr}"
    );
    assert!(files_in(&keep.join("video-frames")).is_empty(), "{stderr}");
    let _ = std::fs::remove_dir_all(&keep);
}

#[test]
fn a_huge_blade_count_under_a_memory_limit_runs_out_of_device_memory_cleanly() {
    // Ten million blades, past the default budget check (--gpu-memory-mib
    // at its maximum), in a process limited to 6 GiB of address space,
    // with validation (the failure path must leave nothing behind).
    // lavapipe's device memory is host memory, so its vkAllocateMemory
    // meets the limit: a real VK_ERROR_OUT_OF_DEVICE_MEMORY. A GPU with
    // enough memory of its own renders it (an H100 did, docs/reliability.md);
    // one without must fail as cleanly.
    let out = temp_out("huge-count");
    let result = Command::new("prlimit")
        .arg(format!("--as={}", 6u64 << 30))
        .arg(env!("CARGO_BIN_EXE_meadow"))
        .args([
            "render",
            "--blades",
            "10000000",
            "--gpu-memory-mib",
            "16777216",
            "--width",
            "64",
            "--height",
            "64",
            "--shadow-map",
            "0",
            "--validation",
            "--out",
            out.to_str().unwrap(),
        ])
        .env("MEADOW_QUIET_VALIDATION", "1")
        // Each lavapipe rasterizer thread reserves address space (stack,
        // malloc arena); pinning their number keeps where the 6 GiB runs
        // out the same on machines with more cores.
        .env("LP_NUM_THREADS", "2")
        .output()
        .expect("prlimit (util-linux) runs");
    let devices = meadow(&["devices"], &[]);
    let only_lavapipe = String::from_utf8_lossy(&devices.stdout)
        .lines()
        .all(|d| d.contains("llvmpipe"));
    if only_lavapipe {
        let stderr = assert_one_clean_line("10M blades in 6 GiB", &result);
        assert!(
            stderr.contains("out of GPU memory while creating blade control points"),
            "{stderr}"
        );
        assert!(files_in(&out).is_empty(), "{:?}", files_in(&out));
    } else if !result.status.success() {
        let stderr = assert_one_clean_line("10M blades in 6 GiB", &result);
        assert!(stderr.contains("memory while creating"), "{stderr}");
        assert!(files_in(&out).is_empty(), "{:?}", files_in(&out));
    } else {
        eprintln!("10M blades fit this device's own memory: nothing ran out");
    }
    let _ = std::fs::remove_dir_all(&out);
}
