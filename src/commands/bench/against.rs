//! `meadow bench --against OLD_BINARY`: one bench run by an older meadow
//! binary and by this one in turn, `runs` times each, the order flipping
//! every run (old, new, then new, old) so that a machine warming up or
//! slowing down weighs on both alike. Each phase's figure is compared as
//! a ratio of runs on one machine in one sitting (new / old, per run, then
//! the median and range over the runs), never as two absolute times from
//! different days. The binaries run as child processes with the same
//! arguments, each writing its bench.json to a folder of its own under
//! the system's temporary folder (removed at the end, on every path);
//! this writes against.json and against.md. It uses only report's output
//! claim and the children's bench.json: no GPU of its own.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::error::{Error, Result};
use crate::report::claim::OutputClaim;
use crate::report::files;

/// Runs of each binary at most.
pub const MAX_AGAINST_RUNS: u32 = 50;

/// What to compare: `bench_args` (`bench` and its arguments, without
/// `--out`) run by `old` and by `new`, `runs` times each.
#[derive(Clone, Debug)]
pub struct AgainstRequest {
    pub old: PathBuf,
    pub new: PathBuf,
    pub bench_args: Vec<String>,
    pub runs: u32,
}

/// One phase of one bench row, by both binaries.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PhaseRatio {
    /// The bench row ("1000 blades, LOD on, culling off") or "wind step".
    pub row: String,
    /// The phase as bench.json names it (wind, grass, shadow, colour,
    /// frame, ...), "wall frame" for the host's frame, or the pressure
    /// solver for the wind step.
    pub phase: String,
    /// Each run's median ms, in run order.
    pub old_ms: Vec<f64>,
    pub new_ms: Vec<f64>,
    /// new / old of each run whose old figure is above zero, median and
    /// range (None where the old figure was zero in every run: a phase
    /// that did nothing).
    pub ratio_median: Option<f64>,
    pub ratio_min: Option<f64>,
    pub ratio_max: Option<f64>,
}

/// against.json.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Against {
    pub old: String,
    pub new: String,
    pub device: String,
    pub runs: u32,
    pub bench_args: Vec<String>,
    /// Which binary ran when ("old", "new", ...).
    pub order: Vec<String>,
    pub phases: Vec<PhaseRatio>,
}

/// The two binaries.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Which {
    Old,
    New,
}

impl Which {
    fn name(self) -> &'static str {
        match self {
            Which::Old => "old",
            Which::New => "new",
        }
    }
}

/// A folder removed when dropped, whatever happened meanwhile.
struct TempDir(PathBuf);

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs the comparison and writes DIR/against.json and against.md
/// (`overwrite` as bench's); `on_run` hears of each bench before it
/// starts (done, total, which binary).
pub fn bench_against(
    request: &AgainstRequest,
    out: &Path,
    overwrite: bool,
    on_run: &mut dyn FnMut(u32, u32, &str),
) -> Result<Against> {
    check(request)?;
    files::ensure_dir(out)?;
    let planned = ["against.json", "against.md"].map(String::from);
    let claim = OutputClaim::new(out, &planned, overwrite)?;
    let work = TempDir(std::env::temp_dir().join(format!("meadow-against-{}", std::process::id())));
    let _ = std::fs::remove_dir_all(&work.0);
    let mut order = Vec::new();
    let mut figures: Vec<(Which, Vec<Figure>)> = Vec::new();
    let mut device: Option<String> = None;
    for run in 0..request.runs {
        let turn = if run % 2 == 0 {
            [Which::Old, Which::New]
        } else {
            [Which::New, Which::Old]
        };
        for which in turn {
            on_run(order.len() as u32, 2 * request.runs, which.name());
            let dir = work.0.join(format!("{}-{run}", which.name()));
            let bench = run_bench(request, which, &dir)?;
            let (ran_on, found) = figures_of(&bench).map_err(|e| {
                Error::InvalidInput(format!(
                    "{}'s bench.json: {e} (is it a meadow binary with `bench`?)",
                    binary(request, which).display()
                ))
            })?;
            match &device {
                Some(d) if *d != ran_on => {
                    return Err(Error::InvalidInput(format!(
                    "the runs found different devices ({d} and {ran_on}): pick one with --device"
                )))
                }
                _ => device = Some(ran_on),
            }
            order.push(which.name().to_string());
            figures.push((which, found));
        }
    }
    let against = Against {
        old: request.old.display().to_string(),
        new: request.new.display().to_string(),
        device: device.unwrap_or_default(),
        runs: request.runs,
        bench_args: request.bench_args.clone(),
        order,
        phases: ratios(&figures),
    };
    claim.begin()?;
    claim.write_json("against.json", &against)?;
    claim.write("against.md", markdown(&against).as_bytes())?;
    Ok(against)
}

fn check(request: &AgainstRequest) -> Result<()> {
    if !request.old.is_file() {
        return Err(Error::InvalidInput(format!(
            "--against {}: no such file; give an older meadow binary (for example target/release/meadow built at the old commit, copied aside)",
            request.old.display()
        )));
    }
    if !(1..=MAX_AGAINST_RUNS).contains(&request.runs) {
        return Err(Error::InvalidInput(format!(
            "--runs {}: between 1 and {MAX_AGAINST_RUNS}",
            request.runs
        )));
    }
    Ok(())
}

fn binary(request: &AgainstRequest, which: Which) -> &Path {
    match which {
        Which::Old => &request.old,
        Which::New => &request.new,
    }
}

/// Runs one bench into `dir` and reads its bench.json back; a failure
/// says which binary failed and its last line.
fn run_bench(request: &AgainstRequest, which: Which, dir: &Path) -> Result<serde_json::Value> {
    let bin = binary(request, which);
    let output = Command::new(bin)
        .args(&request.bench_args)
        .arg("--out")
        .arg(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .map_err(|e| Error::Io {
            path: bin.display().to_string(),
            source: e,
        })?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let last = stderr
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("no message");
        return Err(Error::InvalidInput(format!(
            "the {} binary ({}) failed its bench: {last}",
            which.name(),
            bin.display()
        )));
    }
    let path = dir.join("bench.json");
    let text = std::fs::read_to_string(&path).map_err(|e| {
        Error::InvalidInput(format!(
            "{} wrote no bench.json ({e}): is it a meadow binary with `bench`?",
            bin.display()
        ))
    })?;
    serde_json::from_str(&text)
        .map_err(|e| Error::InvalidInput(format!("{}: not JSON ({e})", path.display())))
}

/// The middle value, or the mean of the two middle values of an even
/// count (with two runs, the mean of both).
fn median(values: &[f64]) -> Option<f64> {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(v[n / 2]),
        _ => Some(0.5 * (v[n / 2 - 1] + v[n / 2])),
    }
}

/// One figure of one bench: (row, phase, median ms).
type Figure = (String, String, f64);

/// The device and every figure of a bench.json: the wind step per
/// pressure solver, then each row's GPU phases and its wall-clock frame.
fn figures_of(bench: &serde_json::Value) -> std::result::Result<(String, Vec<Figure>), String> {
    let device = bench["device"].as_str().ok_or("no device")?.to_string();
    let mut found = Vec::new();
    for solver in bench["wind_solvers"].as_array().ok_or("no wind_solvers")? {
        if let (Some(name), Some(ms)) =
            (solver["solver"].as_str(), solver["step_ms_median"].as_f64())
        {
            found.push(("wind step".to_string(), name.to_string(), ms));
        }
    }
    let rows = bench["rows"].as_array().ok_or("no rows")?;
    // Rows on the ground made flat are named so only beside the terrain's
    // (`--also-flat`); a flat scene's rows are simply its rows.
    let also_flat = rows.iter().any(|r| r["terrain"] == true);
    for row in rows {
        let on = |key: &str| if row[key] == true { "on" } else { "off" };
        let label = format!(
            "{} blades, LOD {}, culling {}{}",
            row["blades"].as_u64().ok_or("a row without blades")?,
            on("lod"),
            on("cull"),
            if also_flat && row["terrain"] == false {
                ", ground made flat"
            } else {
                ""
            }
        );
        let timing = &row["timing"];
        if let Some(phases) = timing["gpu_ms"].as_object() {
            for (phase, spread) in phases {
                if let Some(ms) = spread["median"].as_f64() {
                    found.push((label.clone(), phase.clone(), ms));
                }
            }
        }
        if let Some(ms) = timing["wall_frame_ms"]["median"].as_f64() {
            found.push((label, "wall frame".to_string(), ms));
        }
    }
    if found.is_empty() {
        return Err("no timed figure".into());
    }
    Ok((device, found))
}

/// Each (row, phase) that both binaries timed, in the first bench's
/// order, with its ratios over the runs.
fn ratios(figures: &[(Which, Vec<Figure>)]) -> Vec<PhaseRatio> {
    let mut times: BTreeMap<(String, String), (Vec<f64>, Vec<f64>)> = BTreeMap::new();
    let mut keys: Vec<(String, String)> = Vec::new();
    for (which, found) in figures {
        for (row, phase, ms) in found {
            let key = (row.clone(), phase.clone());
            if !times.contains_key(&key) {
                keys.push(key.clone());
            }
            let entry = times.entry(key).or_default();
            match which {
                Which::Old => entry.0.push(*ms),
                Which::New => entry.1.push(*ms),
            }
        }
    }
    keys.into_iter()
        .filter_map(|key| {
            let (old_ms, new_ms) = times.remove(&key)?;
            if old_ms.len() != new_ms.len() {
                return None; // a phase one binary does not time
            }
            let per_run: Vec<f64> = old_ms
                .iter()
                .zip(&new_ms)
                .filter(|(o, _)| **o > 0.0)
                .map(|(o, n)| n / o)
                .collect();
            let (row, phase) = key;
            Some(PhaseRatio {
                row,
                phase,
                ratio_median: median(&per_run),
                ratio_min: per_run.iter().copied().reduce(f64::min),
                ratio_max: per_run.iter().copied().reduce(f64::max),
                old_ms,
                new_ms,
            })
        })
        .collect()
}

/// against.md: one line per phase, the medians over the runs and the
/// ratio's median and range.
pub fn markdown(a: &Against) -> String {
    let mut md = format!(
        "# {} against {}\n\nbench on {}, {} runs of each, alternating (`meadow {}`)\n\n\
         | row | phase | old ms | new ms | new / old (median, range over runs) |\n|---|---|---|---|---|\n",
        a.new,
        a.old,
        a.device,
        a.runs,
        a.bench_args.join(" ")
    );
    for p in &a.phases {
        let median = |v: &[f64]| median(v).map_or("-".to_string(), |m| format!("{m:.3}"));
        let ratio = match (p.ratio_median, p.ratio_min, p.ratio_max) {
            (Some(m), Some(lo), Some(hi)) => format!("**{m:.3}** ({lo:.3}-{hi:.3})"),
            _ => "- (nothing to time)".to_string(),
        };
        md.push_str(&format!(
            "| {} | {} | {} | {} | {} |\n",
            p.row,
            p.phase,
            median(&p.old_ms),
            median(&p.new_ms),
            ratio
        ));
    }
    md
}
