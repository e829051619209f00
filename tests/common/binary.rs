//! Running the `meadow` binary from the CLI tests.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `meadow args` with `env` added; validation messages counted, not echoed.
pub fn meadow(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_meadow"));
    cmd.args(args).env("MEADOW_QUIET_VALIDATION", "1");
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().expect("run meadow")
}

/// A small scene that renders quickly for the tests that run the binary:
/// fig10's few bunches with a 1024 x 1024 shadow map; with `SMALL_SIZE`
/// unless a test needs another size.
pub const SMALL_SCENE: [&str; 4] = ["--scene", "fig10-few-bunches", "--shadow-map", "1024"];
pub const SMALL_SIZE: [&str; 4] = ["--width", "320", "--height", "180"];

/// Starts `meadow args` in the background (stdout dropped, stderr kept),
/// for tests that signal a running process.
pub fn spawn_meadow(args: &[&str]) -> std::process::Child {
    spawn_meadow_to(args, std::process::Stdio::null())
}

/// As `spawn_meadow`, its standard output going to `stdout`
/// (`Stdio::piped()` for `wait_with_output` to read).
pub fn spawn_meadow_to(args: &[&str], stdout: std::process::Stdio) -> std::process::Child {
    Command::new(env!("CARGO_BIN_EXE_meadow"))
        .args(args)
        .env("MEADOW_QUIET_VALIDATION", "1")
        .stdout(stdout)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start meadow")
}

/// Waits, up to 180 s, until `path` exists; fails if `child` ends first.
pub fn wait_for_file(path: &Path, child: &mut std::process::Child) {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(180);
    while !path.exists() {
        assert!(
            std::time::Instant::now() < deadline,
            "{} never appeared",
            path.display()
        );
        assert!(child.try_wait().unwrap().is_none(), "meadow ended early");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
}

/// Sends SIGINT (Ctrl-C) to `child`.
pub fn send_sigint(child: &std::process::Child) {
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
}

/// `meadow render` of 2000 small frames of fig10's few bunches into
/// `out`, with `extra` arguments, stopped by SIGINT (Ctrl-C) once its
/// fourth frame is on disk: how far an interrupted render got.
pub fn interrupted_render(out: &Path, extra: &[&str]) -> Output {
    let out_arg = out.to_str().unwrap();
    let mut args = vec!["render", "--scene", "fig10-few-bunches", "--frames", "2000"];
    args.extend(["--width", "160", "--height", "90", "--out", out_arg]);
    args.extend(extra);
    let mut child = spawn_meadow(&args);
    wait_for_file(&out.join("frame_0003.png"), &mut child);
    send_sigint(&child);
    child.wait_with_output().unwrap()
}

/// A fresh (removed) directory path under the system temp dir, unique to
/// this test process.
pub fn temp_out(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("meadow-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// A JSON file a command wrote, parsed; panics naming the file.
pub fn read_json(path: &Path) -> serde_json::Value {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_slice(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The names of the files in `dir` (none when it does not exist), sorted:
/// what a run left in its output directory.
pub fn files_in(dir: &Path) -> Vec<String> {
    let entries = match std::fs::read_dir(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Vec::new(),
        entries => entries.unwrap_or_else(|e| panic!("{}: {e}", dir.display())),
    };
    // Not meadow's list of what a run wrote there (report::claim): it is
    // checked where it matters, not in every listing.
    let mut names: Vec<String> = entries
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != meadow::report::claim::MANIFEST_NAME)
        .collect();
    names.sort();
    names
}

/// Fails unless `result` succeeded, showing its stderr.
pub fn assert_succeeded(result: &Output) {
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
}

/// Fails with exactly one stderr line containing `fragment`, and no frame.
pub fn assert_refused(args: &[&str], env: &[(&str, &str)], fragment: &str) {
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
