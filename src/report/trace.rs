//! A trace's files (`meadow trace`, commands/trace.rs): blades.csv and its
//! columns, trace.json, and the diagrams drawn from a trace (space-time,
//! plan view, spectrum) by report::space_time, plan_view and spectrum.
//! It draws and writes what analysis::trace measured; it measures nothing.
//! It uses analysis (the trace), gpu's report types (device memory,
//! validation) and its report siblings.

use std::fmt::Write as _;

use crate::analysis::trace::{
    CellGrid, Percentiles, ScaledSpectrum, Spectrum, TipCorrelation, Trace,
};
use crate::error::{Error, Result};
use crate::gpu::{DeviceMemory, ValidationReport};
use crate::report::plan_view::{self, PlanView};
use crate::report::space_time::{self, SpaceTime};
use crate::report::spectrum::{self as report_spectrum, ScaledPanel, SpectrumChart};

/// The space-time diagram of a trace (report::space_time): 1 m bands along
/// the wind over the traced blades' roots, from `from_s` seconds on.
pub fn space_time_svg(run: &Trace, from_s: f64, title: &str) -> Result<String> {
    let skip = run.samples_before(from_s);
    if skip >= run.times.len() {
        return Err(Error::InvalidInput(format!(
            "the trace ends before {from_s} s: nothing to draw"
        )));
    }
    let (x0, x1) = run
        .roots_in_frame()
        .fold((f32::MAX, f32::MIN), |(lo, hi), r| {
            (lo.min(r[0]), hi.max(r[0]))
        });
    let x0 = x0.floor();
    let bands = (x1 - x0).floor().max(0.0) as usize + 1;
    let values: Vec<Vec<f64>> = run
        .band_displacement(x0, 1.0, bands)
        .into_iter()
        .map(|band| band[skip..].to_vec())
        .collect();
    space_time::svg(&SpaceTime {
        title,
        values: &values,
        x0: x0 as f64,
        band_width: 1.0,
        times: &run.times[skip..],
    })
}

/// The grass from above at three instants a second apart, ending at the
/// trace's last sample (report::plan_view): the traced field in square
/// cells (`CellGrid`), each cell's downwind tip displacement beyond its
/// mean from `from_s` on, in its own standard deviations. None where the
/// trace is shorter than the three instants after `from_s`.
pub fn plan_view_svg(run: &Trace, from_s: f64, title: &str) -> Result<Option<String>> {
    let Some(&end) = run.times.last() else {
        return Ok(None);
    };
    let instants: Vec<f64> = (0..3).map(|k| end - (2 - k) as f64).collect();
    let Some(grid) = CellGrid::of(run).filter(|_| instants[0] >= from_s) else {
        return Ok(None);
    };
    let skip = run.samples_before(from_s);
    let z = space_time::standardised(&grid.displacement(run, skip));
    let times = &run.times[skip..];
    let panels: Vec<(f64, Vec<f64>)> = instants
        .iter()
        .map(|&t| {
            let s = times
                .iter()
                .position(|&u| u >= t - 1e-6)
                .unwrap_or(times.len() - 1);
            // A cell without blades stays blank, not white.
            let values = z
                .iter()
                .zip(&grid.filled)
                .map(|(c, &f)| if f { c[s] } else { f64::NAN })
                .collect();
            (times[s], values)
        })
        .collect();
    let (along, across) = run.frame.axis_names();
    plan_view::svg(&PlanView {
        title,
        axes: (&along, &across),
        x0: grid.corner[0] as f64,
        z0: grid.corner[1] as f64,
        cell: grid.cell as f64,
        nx: grid.nx,
        nz: grid.nz,
        instants: &panels,
    })
    .map(Some)
}

/// The tips' spectrum beside the blades' natural frequencies
/// (report::spectrum).
pub fn spectrum_svg(
    spectrum: &Spectrum,
    scaled: Option<&ScaledSpectrum>,
    bend: Option<&Percentiles>,
    swing: Option<&Percentiles>,
    title: &str,
) -> Result<String> {
    let range = |n: &Percentiles| (n.median, n.p5, n.p95);
    report_spectrum::svg(&SpectrumChart {
        title,
        frequency_hz: &spectrum.frequency_hz,
        power: &spectrum.power,
        bend_hz: bend.map(range),
        swing_hz: swing.map(range),
        scaled: scaled.map(|s| ScaledPanel {
            frequency_over_natural: &s.frequency_over_natural,
            power_per_log_f: &s.power_per_log_f,
        }),
    })
}

/// One column of blades.csv.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Column {
    pub name: &'static str,
    pub unit: &'static str,
    pub meaning: &'static str,
}

/// The columns, with the wind's when it was traced.
pub fn columns(wind: bool) -> Vec<Column> {
    let mut columns = COLUMNS.to_vec();
    if wind {
        columns.extend(WIND_COLUMNS);
    }
    columns
}

pub const WIND_COLUMNS: [Column; 3] = [
    Column {
        name: "wind_x",
        unit: "m/s",
        meaning: "the wind the tip feels (sampled at P3 as the grass step samples it), x",
    },
    Column {
        name: "wind_y",
        unit: "m/s",
        meaning: "the wind at the tip, y",
    },
    Column {
        name: "wind_z",
        unit: "m/s",
        meaning: "the wind at the tip, z",
    },
];

pub const COLUMNS: [Column; 10] = [
    Column {
        name: "time_s",
        unit: "s",
        meaning: "simulated time of the sample (0: the grass at rest, before the first step)",
    },
    Column {
        name: "blade",
        unit: "",
        meaning: "index of the blade in the scene's field (same scene and seed: same blade)",
    },
    Column {
        name: "root_x",
        unit: "m",
        meaning: "root P0, x (world, y up)",
    },
    Column {
        name: "root_z",
        unit: "m",
        meaning: "root P0, z",
    },
    Column {
        name: "tip_x",
        unit: "m",
        meaning: "tip P3, x",
    },
    Column {
        name: "tip_y",
        unit: "m",
        meaning: "tip P3, y (height above the ground)",
    },
    Column {
        name: "tip_z",
        unit: "m",
        meaning: "tip P3, z",
    },
    Column {
        name: "swing",
        unit: "rad",
        meaning: "swing angle about the ground normal (paper section 4)",
    },
    Column {
        name: "bend",
        unit: "rad",
        meaning:
            "bending angle of the (first) bending group, at its tip edge (eq. 12 shares it out)",
    },
    Column {
        name: "twist",
        unit: "rad",
        meaning: "twisting angle of the tip edge about itself",
    },
];

/// trace.json.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TraceReport {
    pub scene: String,
    pub seed: u64,
    pub device: String,
    /// The device memory the run's allocations held at the end and at
    /// most.
    pub device_memory: DeviceMemory,
    pub dt: f32,
    pub substeps: u32,
    /// Simulated seconds and steps the samples cover: what was asked for,
    /// or less when interrupted (then `seconds_planned` and
    /// `steps_planned` say what was asked).
    pub seconds: f64,
    pub every: u32,
    pub steps: u64,
    pub seconds_planned: f64,
    pub steps_planned: u64,
    pub samples: usize,
    pub blades_traced: usize,
    pub blades_total: usize,
    /// The unit (x, z) along which "downwind" and "along the wind" are
    /// read (the inflow's heading; x without an inflow): the spectra,
    /// correlations and diagrams measure the tips' motion along it.
    pub downwind: [f32; 2],
    pub csv: String,
    /// space_time.svg: each 1 m band along the wind, its mean downwind tip
    /// displacement over time (beyond its mean, in its own standard
    /// deviations); travelling waves are diagonal stripes. None for a
    /// single blade or sample.
    pub space_time: Option<String>,
    /// plan_view.svg: the traced field from above at three instants a
    /// second apart, each cell's downwind tip displacement (the space-time
    /// diagram's colours): patches moving downwind. None for a trace
    /// shorter than three seconds past --diagram-from.
    pub plan_view: Option<String>,
    /// spectrum.svg: `tip_spectrum` drawn beside the blades' natural
    /// frequencies. None without a spectrum.
    pub spectrum: Option<String>,
    /// The spectrum of the tips' motion along the wind from `diagram_from`
    /// on, averaged over the traced blades (None: too few samples).
    pub tip_spectrum: Option<Spectrum>,
    /// The same motion per unit log frequency, each blade's frequencies
    /// over its own bending natural frequency: where the blades ring
    /// against where the wind drives them (None: too few samples).
    pub tip_spectrum_scaled: Option<ScaledSpectrum>,
    /// The traced blades' bending natural frequencies (Hz): where the tip
    /// spectrum of a blade that locks in to the wind peaks.
    pub bend_natural_hz: Option<Percentiles>,
    /// The traced blades' swinging natural frequencies (Hz): a blade
    /// standing across the wind moves its tip downwind by swinging, so the
    /// tips' downwind motion rings at both.
    pub swing_natural_hz: Option<Percentiles>,
    /// How far the tips' motion stays alike along and across the wind,
    /// from `diagram_from` on (None on a field under three cells either
    /// way).
    pub tip_correlation: Option<TipCorrelation>,
    pub columns: Vec<Column>,
    /// Stopped early by a signal: the CSV holds the samples taken.
    pub interrupted: bool,
    pub validation: ValidationReport,
}

/// blades.csv: the header, then one row per traced blade per sample.
pub fn csv(trace: &Trace) -> String {
    let mut out = columns(!trace.wind.is_empty())
        .iter()
        .map(|c| c.name)
        .collect::<Vec<_>>()
        .join(",");
    out.push('\n');
    for (s, time) in trace.times.iter().enumerate() {
        for (b, &blade) in trace.blades.iter().enumerate() {
            let tip = trace.tip(s, b);
            let root = trace.roots[b];
            let angles = trace.angles[s * trace.blades.len() + b];
            // Writing to a String cannot fail.
            let _ = write!(
                out,
                "{time:.6},{blade},{},{},{},{},{},{},{},{}",
                root[0], root[1], tip[0], tip[1], tip[2], angles[0], angles[1], angles[2]
            );
            if let Some(w) = trace.wind.get(s * trace.blades.len() + b) {
                let _ = write!(out, ",{},{},{}", w[0], w[1], w[2]);
            }
            out.push('\n');
        }
    }
    out
}

pub const CSV_NAME: &str = "blades.csv";
pub const REPORT_NAME: &str = "trace.json";
pub const SPACE_TIME_NAME: &str = "space_time.svg";
pub const PLAN_VIEW_NAME: &str = "plan_view.svg";
pub const SPECTRUM_NAME: &str = "spectrum.svg";
