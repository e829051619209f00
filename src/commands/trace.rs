//! `meadow trace`: the grass's motion as data for analysis. The scene is
//! simulated on the GPU (wind and grass, no rendering) for a number of
//! seconds; every `every` steps the traced blades' roots, tips and angles
//! are read back. Writes DIR/blades.csv (one row per traced blade per
//! sample), DIR/trace.json (what the columns are, in which units, and
//! where the numbers came from) and DIR/space_time.svg (the motion along x
//! over time).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use crate::analysis::stats::lagged_correlation;
use crate::commands::on_gpu;
use crate::compute::{Simulation, StepPace};
use crate::error::{Error, Result};
use crate::frame::BladeBuffer;
use crate::gpu::{CommandPool, DeviceMemory, Gpu, GpuOptions, ValidationReport};
use crate::model::grass::{BEND_A, SWING, TWIST};
use crate::model::wind::WindField;
use crate::model::BladeVertex;
use crate::report::claim::OutputClaim;
use crate::report::files;
use crate::report::plan_view::{self, PlanView};
use crate::report::space_time::{self, SpaceTime};
use crate::report::spectrum::{self as report_spectrum, ScaledPanel, SpectrumChart};
use crate::scene::{field, Scene};
use glam::Vec3;

/// Longest trace, simulated seconds.
pub const MAX_SECONDS: f64 = 3600.0;
/// Largest sampling interval, in steps.
pub const MAX_EVERY: u32 = 100_000;

/// Which blades to trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BladePick {
    /// This many, one from each of as many equal runs of the field's
    /// blades, where in its run picked by the scene's seed.
    Count(usize),
    All,
}

impl BladePick {
    /// `--blades`: a count or "all".
    pub fn parse(text: &str) -> Result<Self> {
        if text.trim() == "all" {
            return Ok(BladePick::All);
        }
        match text.trim().parse::<usize>() {
            Ok(n) if n >= 1 => Ok(BladePick::Count(n)),
            _ => Err(Error::InvalidInput(format!(
                "--blades {text} is not allowed, use a count of 1 or more, or all"
            ))),
        }
    }

    /// The traced blades' indices among `total`, ascending.
    /// How many blades of `total` it picks.
    pub fn count(self, total: usize) -> usize {
        match self {
            BladePick::All => total,
            BladePick::Count(n) => n.min(total),
        }
    }

    pub fn indices(self, total: usize, seed: u64) -> Vec<u32> {
        let count = self.count(total);
        if count == total {
            return (0..total as u32).collect();
        }
        (0..count)
            .map(|i| {
                let start = i * total / count;
                let end = (i + 1) * total / count;
                let u = unit_hash(seed, i as u64);
                (start + ((u * (end - start) as f64) as usize).min(end - start - 1)) as u32
            })
            .collect()
    }
}

/// A uniform number in [0, 1) from a seed and an index (splitmix64).
fn unit_hash(seed: u64, index: u64) -> f64 {
    let mut z = seed
        .wrapping_add(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(index.wrapping_mul(0xBF58_476D_1CE4_E5B9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

#[derive(Clone, Debug)]
pub struct TraceRequest {
    pub scene: Scene,
    /// Simulated seconds (whole steps of the scene's dt, rounded).
    pub seconds: f64,
    /// A sample every this many steps (1: every step).
    pub every: u32,
    pub blades: BladePick,
    /// Also the wind each traced tip feels (columns wind_x, wind_y, wind_z).
    pub wind: bool,
    /// space_time.svg starts here (s): the first seconds, the grass
    /// leaning into a wind that fills the field, can outweigh the waves.
    pub diagram_from: f64,
    pub gpu: GpuOptions,
}

impl TraceRequest {
    pub fn validate(&self) -> Result<()> {
        if !(self.seconds > 0.0 && self.seconds <= MAX_SECONDS) {
            return Err(Error::InvalidInput(format!(
                "--seconds {} is not allowed, use more than 0 and at most {MAX_SECONDS}",
                self.seconds
            )));
        }
        if !(0.0..self.seconds).contains(&self.diagram_from) {
            return Err(Error::InvalidInput(format!(
                "--diagram-from {} is not allowed, use 0 or more and less than --seconds {}",
                self.diagram_from, self.seconds
            )));
        }
        if !(1..=MAX_EVERY).contains(&self.every) {
            return Err(Error::InvalidInput(format!(
                "--every {} is not allowed, use 1..={MAX_EVERY}",
                self.every
            )));
        }
        self.scene.validate()?;
        self.scene.wind_grid()?;
        Ok(())
    }

    /// Simulation steps the trace runs.
    pub fn steps(&self) -> u64 {
        (self.seconds / self.scene.wind.dt as f64).round().max(1.0) as u64
    }
}

/// The traced blades over time, in memory: sample s, blade b at
/// `[s * blades.len() + b]`.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    pub dt: f32,
    pub substeps: u32,
    /// Indices of the traced blades in the scene's field.
    pub blades: Vec<u32>,
    /// Root (x, z) of each traced blade, m.
    pub roots: Vec<[f32; 2]>,
    /// Simulated time of each sample, s.
    pub times: Vec<f64>,
    /// Tip (P3) of each traced blade at each sample, m.
    pub tips: Vec<[f32; 3]>,
    /// (swing, bend, twist) of each traced blade at each sample, rad.
    pub angles: Vec<[f32; 3]>,
    /// The wind at each traced tip at each sample (m/s), when asked for.
    pub wind: Vec<[f32; 3]>,
    /// Each traced blade's bending natural frequency (Hz,
    /// `GrassBlade::natural_frequency_hz`).
    pub bend_hz: Vec<f64>,
    /// Each traced blade's swinging natural frequency (Hz), the same way.
    pub swing_hz: Vec<f64>,
    /// Blades in the field.
    pub total_blades: usize,
    /// Steps simulated: all asked for, or up to the last sample when
    /// interrupted.
    pub steps_done: u64,
    pub interrupted: bool,
}

impl Trace {
    /// Samples taken before `from_s` seconds: where the statistics and
    /// diagrams from `from_s` on begin.
    pub fn samples_before(&self, from_s: f64) -> usize {
        self.times.iter().take_while(|&&t| t < from_s).count()
    }

    /// Blade b's tip at sample s.
    pub fn tip(&self, sample: usize, blade: usize) -> [f32; 3] {
        self.tips[sample * self.blades.len() + blade]
    }
}

impl Trace {
    /// The mean downwind tip displacement (tip x now minus tip x at the
    /// first sample) of the traced blades rooted in each band of
    /// `band_width` metres along x from `x0`, per sample: `[band][sample]`.
    /// A band without blades is all zeros.
    pub fn band_displacement(&self, x0: f32, band_width: f32, bands: usize) -> Vec<Vec<f64>> {
        self.grouped_displacement(bands, |root| {
            let band = ((root[0] - x0) / band_width).floor();
            (0.0..bands as f32).contains(&band).then_some(band as usize)
        })
    }

    /// As `band_displacement`, over square cells of `cell` metres from
    /// (x0, z0), `nx` along x and `nz` along z: `[iz * nx + ix][sample]`.
    pub fn cell_displacement(
        &self,
        corner: [f32; 2],
        cell: f32,
        nx: usize,
        nz: usize,
    ) -> Vec<Vec<f64>> {
        self.grouped_displacement(nx * nz, |root| {
            let ix = ((root[0] - corner[0]) / cell).floor();
            let iz = ((root[1] - corner[1]) / cell).floor();
            ((0.0..nx as f32).contains(&ix) && (0.0..nz as f32).contains(&iz))
                .then_some(iz as usize * nx + ix as usize)
        })
    }

    /// Cells (or bands) whose traced blades share no group are all zeros.
    fn grouped_displacement(
        &self,
        groups: usize,
        group_of: impl Fn([f32; 2]) -> Option<usize>,
    ) -> Vec<Vec<f64>> {
        let n = self.blades.len();
        let mut sum = vec![vec![0.0f64; self.times.len()]; groups];
        let mut count = vec![0usize; groups];
        for (b, root) in self.roots.iter().enumerate() {
            let Some(group) = group_of(*root) else {
                continue;
            };
            count[group] += 1;
            let rest = self.tips[b][0];
            for (s, total) in sum[group].iter_mut().enumerate() {
                *total += (self.tips[s * n + b][0] - rest) as f64;
            }
        }
        for (series, &c) in sum.iter_mut().zip(&count) {
            series.iter_mut().for_each(|v| *v /= c.max(1) as f64);
        }
        sum
    }
}

/// A power spectrum: `power[i]` (m^2 / Hz) at `frequency_hz[i]`.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct Spectrum {
    /// The frequency the power is largest at (Hz).
    pub peak_hz: f64,
    /// Seconds of samples it was taken over, and from when.
    pub seconds: f64,
    pub from_s: f64,
    pub frequency_hz: Vec<f64>,
    pub power: Vec<f64>,
}

/// `Trace::scaled_tip_spectrum`: the tips' motion per unit log frequency,
/// each blade against its own bending natural frequency.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ScaledSpectrum {
    /// f / f_bend at the centre of the largest band (1: the band from
    /// 2^(-1/8) to 2^(1/8) of f_bend).
    pub peak_over_natural: f64,
    /// Whether that is the slowest band: then the motion has no peak, only
    /// the wind's slowest eddies.
    pub peak_is_slowest_band: bool,
    /// Blades averaged (those that move and ring).
    pub blades: usize,
    pub seconds: f64,
    pub from_s: f64,
    /// Centres of the quarter-octave bands, f / f_bend.
    pub frequency_over_natural: Vec<f64>,
    /// f S(f) / variance in each band, averaged over the blades.
    pub power_per_log_f: Vec<f64>,
}

/// The one-sided periodogram of `series` sampled every `dt` seconds, its
/// mean taken off and a Hann window applied (power scaled back by the
/// window's mean square), from 1 / T up to the Nyquist frequency. A direct
/// DFT: traces hold hundreds of samples, not millions.
pub fn periodogram(series: &[f64], dt: f64) -> Vec<(f64, f64)> {
    let n = series.len();
    if n < 4 {
        return Vec::new();
    }
    let mean = series.iter().sum::<f64>() / n as f64;
    let window: Vec<f64> = (0..n)
        .map(|j| 0.5 - 0.5 * (std::f64::consts::TAU * j as f64 / (n - 1) as f64).cos())
        .collect();
    let window_power = window.iter().map(|w| w * w).sum::<f64>();
    (1..=n / 2)
        .map(|k| {
            let (mut re, mut im) = (0.0, 0.0);
            for (j, (v, w)) in series.iter().zip(&window).enumerate() {
                let phase = std::f64::consts::TAU * (k * j) as f64 / n as f64;
                re += (v - mean) * w * phase.cos();
                im -= (v - mean) * w * phase.sin();
            }
            // One-sided density: twice the two-sided one but at Nyquist.
            let sides = if 2 * k == n { 1.0 } else { 2.0 };
            let density = sides * (re * re + im * im) * dt / window_power;
            (k as f64 / (n as f64 * dt), density)
        })
        .collect()
}

impl Trace {
    /// The spectrum of the tips' downwind (x) motion from `from_s` on: each
    /// traced blade's periodogram, averaged over the blades. None with
    /// fewer than 8 samples after `from_s`.
    pub fn tip_spectrum(&self, from_s: f64) -> Option<Spectrum> {
        let n = self.blades.len();
        self.mean_spectrum(from_s, |s, b| self.tips[s * n + b][0] as f64)
    }

    /// As `tip_spectrum`, of `value(sample, blade)` (the wind at the tip,
    /// say): each traced blade's periodogram from `from_s` on, averaged.
    pub fn mean_spectrum(
        &self,
        from_s: f64,
        value: impl Fn(usize, usize) -> f64,
    ) -> Option<Spectrum> {
        let skip = self.samples_before(from_s);
        let samples = self.times.len().saturating_sub(skip);
        if samples < 8 || self.blades.is_empty() {
            return None;
        }
        let dt = self.times[1] - self.times[0];
        let n = self.blades.len();
        let mut power: Vec<f64> = Vec::new();
        let mut frequency_hz = Vec::new();
        for b in 0..n {
            let series: Vec<f64> = (skip..self.times.len()).map(|s| value(s, b)).collect();
            let spectrum = periodogram(&series, dt);
            if power.is_empty() {
                power = vec![0.0; spectrum.len()];
                frequency_hz = spectrum.iter().map(|&(f, _)| f).collect();
            }
            for (total, (_, p)) in power.iter_mut().zip(spectrum) {
                *total += p / n as f64;
            }
        }
        let peak = power
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map(|(i, _)| frequency_hz[i])?;
        Some(Spectrum {
            peak_hz: peak,
            seconds: samples as f64 * dt,
            from_s: self.times[skip],
            frequency_hz,
            power,
        })
    }

    /// The tips' downwind motion against each blade's own bending natural
    /// frequency: each traced blade's periodogram from `from_s` on, its
    /// frequencies divided by the blade's f_bend and its power read per
    /// unit log frequency as a share of its variance (f S(f) / var, whose
    /// integral over ln f is 1), averaged in quarter-octave bands of f /
    /// f_bend over the blades. The blades' natural frequencies spread over
    /// a factor of two, so `tip_spectrum`, in hertz, smears the ringing of
    /// each over them all; this lines them up. None with fewer than 8
    /// samples or no blade that both moves and rings (f_bend > 0).
    pub fn scaled_tip_spectrum(&self, from_s: f64) -> Option<ScaledSpectrum> {
        const BANDS_PER_OCTAVE: f64 = 4.0;
        let skip = self.samples_before(from_s);
        let samples = self.times.len().saturating_sub(skip);
        if samples < 8 || self.blades.is_empty() {
            return None;
        }
        let dt = self.times[1] - self.times[0];
        let n = self.blades.len();
        // Bands centred on powers of 2^(1/4), one of them on f_bend itself.
        let band_of = |ratio: f64| (ratio.log2() * BANDS_PER_OCTAVE).round() as i64;
        // band -> (sum of the blades' band means, blades with the band)
        let mut bands: BTreeMap<i64, (f64, usize)> = Default::default();
        let mut blades = 0usize;
        for b in 0..n {
            let natural = self.bend_hz.get(b).copied().unwrap_or(0.0);
            let series: Vec<f64> = (skip..self.times.len())
                .map(|s| self.tips[s * n + b][0] as f64)
                .collect();
            let periodogram = periodogram(&series, dt);
            let variance: f64 =
                periodogram.iter().map(|(_, p)| p).sum::<f64>() / (dt * samples as f64);
            if natural <= 0.0 || variance <= 0.0 {
                continue;
            }
            blades += 1;
            let mut own: BTreeMap<i64, (f64, usize)> = Default::default();
            for (f, p) in periodogram {
                let entry = own.entry(band_of(f / natural)).or_default();
                entry.0 += f * p / variance;
                entry.1 += 1;
            }
            for (band, (sum, count)) in own {
                let entry = bands.entry(band).or_default();
                entry.0 += sum / count as f64;
                entry.1 += 1;
            }
        }
        // A band only some blades reach (the slowest and fastest ends) is
        // left out: its mean is over a few blades, not the field.
        let (frequency_over_natural, power_per_log_f): (Vec<f64>, Vec<f64>) = bands
            .into_iter()
            .filter(|(_, (_, count))| 2 * count >= blades)
            .map(|(band, (sum, count))| {
                let centre = (band as f64 / BANDS_PER_OCTAVE).exp2();
                (centre, sum / count as f64)
            })
            .unzip();
        let peak = power_per_log_f
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map(|(i, _)| i)?;
        Some(ScaledSpectrum {
            peak_over_natural: frequency_over_natural[peak],
            peak_is_slowest_band: peak == 0,
            blades,
            seconds: samples as f64 * dt,
            from_s: self.times[skip],
            frequency_over_natural,
            power_per_log_f,
        })
    }

    /// The traced blades' bending natural frequencies: median, 5th and
    /// 95th percentiles (Hz). None without blades.
    pub fn bend_natural_hz(&self) -> Option<Percentiles> {
        Percentiles::of(&self.bend_hz)
    }

    /// The traced blades' swinging natural frequencies, the same way: a
    /// blade standing across the wind moves its tip downwind by swinging.
    pub fn swing_natural_hz(&self) -> Option<Percentiles> {
        Percentiles::of(&self.swing_hz)
    }
}

/// Median and the 5th and 95th percentiles of a set of values.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct Percentiles {
    pub median: f64,
    pub p5: f64,
    pub p95: f64,
}

impl Percentiles {
    pub fn of(values: &[f64]) -> Option<Self> {
        if values.is_empty() {
            return None;
        }
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
        Some(Self {
            median: at(0.5),
            p5: at(0.05),
            p95: at(0.95),
        })
    }
}

/// The space-time diagram of a trace (report::space_time): 1 m bands along
/// x over the traced blades' roots, from `from_s` seconds on.
pub fn space_time_svg(run: &Trace, from_s: f64, title: &str) -> Result<String> {
    let skip = run.samples_before(from_s);
    if skip >= run.times.len() {
        return Err(Error::InvalidInput(format!(
            "the trace ends before {from_s} s: nothing to draw"
        )));
    }
    let (x0, x1) = run.roots.iter().fold((f32::MAX, f32::MIN), |(lo, hi), r| {
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

/// The traced blades' roots in square cells: where the plan view and the
/// tips' correlation look.
struct CellGrid {
    corner: [f32; 2],
    cell: f32,
    nx: usize,
    nz: usize,
    /// Whether each cell (`iz * nx + ix`) holds a traced blade.
    filled: Vec<bool>,
}

impl CellGrid {
    /// Cells of 2 m, or larger so that there are at most 40 along a side
    /// and about 20 traced blades in a cell on average. None without
    /// blades.
    fn of(run: &Trace) -> Option<Self> {
        if run.roots.is_empty() {
            return None;
        }
        let fold = |i: usize| {
            run.roots.iter().fold((f32::MAX, f32::MIN), |(lo, hi), r| {
                (lo.min(r[i]), hi.max(r[i]))
            })
        };
        let ((x0, x1), (z0, z1)) = (fold(0), fold(1));
        let area = ((x1 - x0) * (z1 - z0)).max(1.0);
        let per_m2 = run.roots.len() as f32 / area;
        let cell = 2.0f32
            .max((x1 - x0).max(z1 - z0) / 40.0)
            .max((20.0 / per_m2).sqrt());
        let corner = [(x0 / cell).floor() * cell, (z0 / cell).floor() * cell];
        let nx = ((x1 - corner[0]) / cell).floor() as usize + 1;
        let nz = ((z1 - corner[1]) / cell).floor() as usize + 1;
        let mut filled = vec![false; nx * nz];
        for r in &run.roots {
            let ix = (((r[0] - corner[0]) / cell) as usize).min(nx - 1);
            let iz = (((r[1] - corner[1]) / cell) as usize).min(nz - 1);
            filled[iz * nx + ix] = true;
        }
        Some(Self {
            corner,
            cell,
            nx,
            nz,
            filled,
        })
    }

    /// Each cell's mean downwind tip displacement from sample `skip` on:
    /// `[iz * nx + ix][sample]`.
    fn displacement(&self, run: &Trace, skip: usize) -> Vec<Vec<f64>> {
        run.cell_displacement(self.corner, self.cell, self.nx, self.nz)
            .into_iter()
            .map(|c| c[skip..].to_vec())
            .collect()
    }
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
    plan_view::svg(&PlanView {
        title,
        x0: grid.corner[0] as f64,
        z0: grid.corner[1] as f64,
        cell: grid.cell as f64,
        nx: grid.nx,
        nz: grid.nz,
        instants: &panels,
    })
    .map(Some)
}

/// How far the tips' motion stays alike across the field: the mean
/// correlation (lag 0) of the downwind tip displacement of two cells
/// (`CellGrid`) at each separation along the wind (x: the trace measures
/// the displacement along x) and across it (z), their integral lengths,
/// and the correlation of two bands along the wind 20 m apart across it
/// (the test of patches against fronts). Each series' straight-line
/// trend over the window is taken off first: the mean wind still settling
/// over the field bends every tip alike and slowly, which is not a gust.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TipCorrelation {
    pub cell_m: f64,
    pub from_s: f64,
    /// Separations (m), and the mean correlation at each.
    pub separation_m: Vec<f64>,
    pub along: Vec<f64>,
    pub across: Vec<f64>,
    /// The integral of the correlation from 0 (where it is 1) to its first
    /// zero, or to the largest separation if it stays above zero (then a
    /// lower bound): m.
    pub along_length_m: f64,
    pub across_length_m: f64,
    /// Bands one cell wide along the whole field, their centres 20 m apart
    /// across the wind: the mean correlation of their mean displacements.
    /// None on a field narrower than 20 m plus a cell.
    pub bands_20m_across: Option<f64>,
}

impl Trace {
    /// The tips' correlation from `from_s` on (`TipCorrelation`); None
    /// where the field is under two cells either way or there are fewer
    /// than 8 samples.
    pub fn tip_correlation(&self, from_s: f64) -> Option<TipCorrelation> {
        let grid = CellGrid::of(self)?;
        let skip = self.samples_before(from_s);
        if self.times.len() < skip + 8 || grid.nx < 3 || grid.nz < 3 {
            return None;
        }
        let cells: Vec<Vec<f64>> = grid
            .displacement(self, skip)
            .into_iter()
            .map(detrended)
            .collect();
        let at = |ix: usize, iz: usize| -> Option<&Vec<f64>> {
            grid.filled[iz * grid.nx + ix].then(|| &cells[iz * grid.nx + ix])
        };
        let mean_correlation = |pairs: &mut dyn Iterator<Item = (&Vec<f64>, &Vec<f64>)>| {
            let (sum, n) = pairs.fold((0.0, 0usize), |(sum, n), (a, b)| {
                let r = lagged_correlation(a, b, 0);
                if r.is_finite() {
                    (sum + r, n + 1)
                } else {
                    (sum, n)
                }
            });
            (n > 0).then(|| sum / n as f64)
        };
        let largest = grid.nx.min(grid.nz) / 2;
        let (mut along, mut across) = (Vec::new(), Vec::new());
        for k in 1..=largest {
            let mut pairs_along = (0..grid.nz).flat_map(|iz| {
                (0..grid.nx - k).filter_map(move |ix| Some((at(ix, iz)?, at(ix + k, iz)?)))
            });
            let mut pairs_across = (0..grid.nz - k).flat_map(|iz| {
                (0..grid.nx).filter_map(move |ix| Some((at(ix, iz)?, at(ix, iz + k)?)))
            });
            along.push(mean_correlation(&mut pairs_along).unwrap_or(0.0));
            across.push(mean_correlation(&mut pairs_across).unwrap_or(0.0));
        }
        let cell = grid.cell as f64;
        // Bands along the wind: each row of cells averaged.
        let rows: Vec<Vec<f64>> = (0..grid.nz)
            .map(|iz| {
                let row: Vec<&Vec<f64>> = (0..grid.nx).filter_map(|ix| at(ix, iz)).collect();
                let n = row.len().max(1) as f64;
                (0..cells[0].len())
                    .map(|s| row.iter().map(|c| c[s]).sum::<f64>() / n)
                    .collect()
            })
            .collect();
        let gap = (20.0 / cell).round() as usize;
        let mut band_pairs =
            (0..grid.nz.saturating_sub(gap)).map(|iz| (&rows[iz], &rows[iz + gap]));
        let bands_20m_across = (gap >= 1 && gap < grid.nz)
            .then(|| mean_correlation(&mut band_pairs))
            .flatten();
        Some(TipCorrelation {
            cell_m: cell,
            from_s,
            separation_m: (1..=largest).map(|k| k as f64 * cell).collect(),
            along_length_m: integral_length(&along, cell),
            across_length_m: integral_length(&across, cell),
            along,
            across,
            bands_20m_across,
        })
    }
}

/// `series` less its least-squares straight line.
fn detrended(series: Vec<f64>) -> Vec<f64> {
    let n = series.len() as f64;
    let t_mean = (n - 1.0) / 2.0;
    let mean = series.iter().sum::<f64>() / n;
    let (mut ty, mut tt) = (0.0, 0.0);
    for (t, v) in series.iter().enumerate() {
        let dt = t as f64 - t_mean;
        ty += dt * (v - mean);
        tt += dt * dt;
    }
    let slope = if tt > 0.0 { ty / tt } else { 0.0 };
    series
        .iter()
        .enumerate()
        .map(|(t, v)| v - mean - slope * (t as f64 - t_mean))
        .collect()
}

/// The integral of a correlation given at separations `step`, 2 `step`,
/// ... (1 at 0), by trapezoids up to its first zero.
fn integral_length(correlation: &[f64], step: f64) -> f64 {
    let mut length = 0.0;
    let mut before = 1.0;
    for &r in correlation {
        if r <= 0.0 {
            // The last piece, down to where the straight line crosses 0.
            return length + step * before / (before - r) * before / 2.0;
        }
        length += step * (before + r) / 2.0;
        before = r;
    }
    length
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

/// Simulates `request`'s scene on `gpu`, sampling from t = 0. `observer`
/// is asked after each sample, and after each submission of steps between
/// samples, whether to go on (false: stop, the trace ending at its last
/// sample and marked interrupted).
pub fn trace(
    gpu: &Gpu,
    request: &TraceRequest,
    observer: &mut dyn FnMut(u64, u64) -> bool,
) -> Result<Trace> {
    let scene = &request.scene;
    let rest = scene.field()?;
    let dynamic = field::dynamic_blades(&rest, &scene.grass.dynamics, scene.seed)?;
    let commands = CommandPool::new(gpu, "trace commands")?;
    let vertices = BladeBuffer::new(gpu, &commands, &rest)?;
    let mut simulation = Simulation::new(gpu, &commands, scene, &dynamic, vertices.buffer())?;
    let blades = request.blades.indices(rest.len(), scene.seed);
    // The CPU field only samples what the GPU's wind read back.
    let mut wind = request
        .wind
        .then(|| -> Result<WindField> {
            Ok(WindField::new(scene.wind_grid()?, &scene.wind_settings()))
        })
        .transpose()?;
    let mut trace = Trace {
        dt: simulation.dt(),
        substeps: simulation.substeps(),
        roots: blades
            .iter()
            .map(|&b| {
                let p = rest[b as usize].rest[0];
                [p.x, p.z]
            })
            .collect(),
        bend_hz: blades
            .iter()
            .map(|&b| dynamic[b as usize].natural_frequency_hz(BEND_A))
            .collect(),
        swing_hz: blades
            .iter()
            .map(|&b| dynamic[b as usize].natural_frequency_hz(SWING))
            .collect(),
        blades,
        total_blades: rest.len(),
        ..Trace::default()
    };
    let steps = request.steps();
    let mut done = 0u64;
    let mut pace = StepPace::default();
    'samples: loop {
        sample(
            gpu,
            &commands,
            &simulation,
            &vertices,
            wind.as_mut(),
            &mut trace,
            done,
        )?;
        trace.steps_done = done;
        if done >= steps {
            break;
        }
        if !observer(done, steps) {
            trace.interrupted = true;
            break;
        }
        // The steps to the next sample, in submissions paced to the
        // machine, a stop asked after each (the trace then ends at the
        // last sample).
        let mut left = (request.every as u64).min(steps - done);
        while left > 0 {
            left -= pace.run(left, |batch| {
                let rec = commands.begin()?;
                simulation.record_steps(&rec, batch);
                rec.submit_and_wait("simulating a trace")
            })?;
            if left > 0 && !observer(done, steps) {
                trace.interrupted = true;
                break 'samples;
            }
        }
        done += request.every as u64;
        done = done.min(steps);
    }
    drop(simulation);
    Ok(trace)
}

/// Reads the traced blades' tips and angles after `step` steps.
fn sample(
    gpu: &Gpu,
    commands: &CommandPool,
    simulation: &Simulation,
    vertices: &BladeBuffer,
    wind: Option<&mut WindField>,
    trace: &mut Trace,
    step: u64,
) -> Result<()> {
    let all: Vec<BladeVertex> =
        vertices
            .buffer()
            .read_back(gpu, commands, 4 * trace.total_blades)?;
    let states = simulation
        .grass()
        .ok_or_else(|| {
            Error::InvalidInput(
                "trace follows the patches' blades and this scene's only grass is a [grass.cover]; add a [[grass.meadow]] or pick another scene".into(),
            )
        })?
        .read_states(gpu, commands)?;
    trace.times.push(step as f64 * trace.dt as f64);
    for &b in &trace.blades {
        let tip = all[4 * b as usize + 3].position;
        trace.tips.push([tip[0], tip[1], tip[2]]);
        let a = states[b as usize].angle;
        trace.angles.push([a[SWING], a[BEND_A], a[TWIST]]);
    }
    if let Some(field) = wind {
        field.vel = simulation.wind().read_velocity(gpu, commands)?;
        field.subgrid_turbulence = simulation.wind().subgrid_records();
        let first = trace.tips.len() - trace.blades.len();
        for tip in &trace.tips[first..] {
            // What the tip feels: the grid's wind and the turbulence finer
            // than the grid there.
            trace.wind.push(field.felt(Vec3::from(*tip)).to_array());
        }
    }
    Ok(())
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
    pub csv: String,
    /// space_time.svg: each 1 m band along x, its mean downwind tip
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
    /// The spectrum of the tips' downwind (x) motion from `diagram_from`
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

/// Runs the trace and writes DIR/blades.csv, DIR/trace.json and (with two
/// samples and blades or more) DIR/space_time.svg, DIR/plan_view.svg (when
/// the trace lasts three seconds past `diagram_from`) and DIR/spectrum.svg
/// (when there is a spectrum), replacing only an
/// earlier run's (`overwrite`: any file of those names; `report::claim`).
pub fn trace_to_dir(
    request: &TraceRequest,
    out: &Path,
    overwrite: bool,
    observer: &mut dyn FnMut(u64, u64) -> bool,
) -> Result<TraceReport> {
    request.validate()?;
    files::ensure_dir(out)?;
    let planned: Vec<String> = [
        CSV_NAME,
        REPORT_NAME,
        SPACE_TIME_NAME,
        PLAN_VIEW_NAME,
        SPECTRUM_NAME,
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let claim = OutputClaim::new(out, &planned, overwrite)?;
    // blades.csv: a row per traced blade and sample, at least 30 bytes
    // (ten numbers and their commas).
    let blades = request.blades.count(request.scene.blade_count()) as u64;
    let samples = request.steps().div_ceil(request.every as u64) + 1;
    claim.ensure_room(
        samples * blades * 30,
        &format!("{samples} samples of {blades} blades in {CSV_NAME}"),
    )?;
    let ((trace, device, device_memory), validation) = on_gpu(&request.gpu, |gpu| {
        Ok((
            trace(gpu, request, observer)?,
            gpu.info().name.clone(),
            gpu.device_memory(),
        ))
    })?;
    // The work is done: the last run's files go (its diagram too, which
    // would pass for this one's).
    claim.begin()?;
    claim.write(CSV_NAME, csv(&trace).as_bytes())?;
    let title = format!("{}: tip displacement along x over time", request.scene.name);
    let diagram = (trace.blades.len() > 1 && trace.times.len() > 1)
        .then(|| space_time_svg(&trace, request.diagram_from, &title))
        .transpose()?;
    if let Some(svg) = &diagram {
        claim.write(SPACE_TIME_NAME, svg.as_bytes())?;
    }
    let title = format!(
        "{}: tips bent downwind from above, a second apart",
        request.scene.name
    );
    let plan_view = (trace.blades.len() > 1)
        .then(|| plan_view_svg(&trace, request.diagram_from, &title))
        .transpose()?
        .flatten();
    if let Some(svg) = &plan_view {
        claim.write(PLAN_VIEW_NAME, svg.as_bytes())?;
    }
    let tip_spectrum = trace.tip_spectrum(request.diagram_from);
    let tip_spectrum_scaled = trace.scaled_tip_spectrum(request.diagram_from);
    let bend_natural_hz = trace.bend_natural_hz();
    let swing_natural_hz = trace.swing_natural_hz();
    let title = format!("{}: the tips' spectrum", request.scene.name);
    let spectrum = tip_spectrum
        .as_ref()
        .map(|s| {
            spectrum_svg(
                s,
                tip_spectrum_scaled.as_ref(),
                bend_natural_hz.as_ref(),
                swing_natural_hz.as_ref(),
                &title,
            )
        })
        .transpose()?;
    if let Some(svg) = &spectrum {
        claim.write(SPECTRUM_NAME, svg.as_bytes())?;
    }
    let report = TraceReport {
        scene: request.scene.name.clone(),
        seed: request.scene.seed,
        device,
        device_memory,
        dt: trace.dt,
        substeps: trace.substeps,
        seconds: if trace.interrupted {
            trace.steps_done as f64 * trace.dt as f64
        } else {
            request.seconds
        },
        every: request.every,
        steps: trace.steps_done,
        seconds_planned: request.seconds,
        steps_planned: request.steps(),
        samples: trace.times.len(),
        blades_traced: trace.blades.len(),
        blades_total: trace.total_blades,
        csv: CSV_NAME.into(),
        space_time: diagram.map(|_| SPACE_TIME_NAME.into()),
        plan_view: plan_view.map(|_| PLAN_VIEW_NAME.into()),
        spectrum: spectrum.map(|_| SPECTRUM_NAME.into()),
        tip_spectrum,
        tip_spectrum_scaled,
        bend_natural_hz,
        swing_natural_hz,
        tip_correlation: trace.tip_correlation(request.diagram_from),
        columns: columns(request.wind),
        interrupted: trace.interrupted,
        validation,
    };
    claim.write_json(REPORT_NAME, &report)?;
    report.validation.check()?;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_periodogram_of_a_sine_peaks_at_its_frequency_with_its_power() {
        // 0.9 Hz of amplitude 0.02 m sampled at 10 Hz for 40 s (a whole
        // number of periods: the peak falls on a bin).
        let (dt, f0, a) = (0.1, 0.9, 0.02);
        let series: Vec<f64> = (0..400)
            .map(|j| 0.3 + a * (std::f64::consts::TAU * f0 * j as f64 * dt).sin())
            .collect();
        let spectrum = periodogram(&series, dt);
        assert_eq!(spectrum.len(), 200);
        assert!((spectrum[0].0 - 0.025).abs() < 1e-12);
        assert!((spectrum[199].0 - 5.0).abs() < 1e-12, "up to Nyquist");
        let (peak, _) = spectrum
            .iter()
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .copied()
            .unwrap();
        assert!((peak - f0).abs() < 1e-9, "peak at {peak}");
        // Parseval: the power integrates to the variance, a^2 / 2, within
        // the Hann window's leakage at the edges.
        let variance: f64 = spectrum.iter().map(|&(_, p)| p * 0.025).sum();
        assert!((variance / (a * a / 2.0) - 1.0).abs() < 0.02, "{variance}");
    }

    #[test]
    fn a_pick_takes_one_blade_from_each_equal_run_and_depends_on_the_seed() {
        let picked = BladePick::Count(10).indices(1000, 7);
        assert_eq!(picked.len(), 10);
        for (i, &b) in picked.iter().enumerate() {
            assert!(
                (100 * i as u32..100 * (i as u32 + 1)).contains(&b),
                "{picked:?}"
            );
        }
        assert_eq!(picked, BladePick::Count(10).indices(1000, 7));
        assert_ne!(picked, BladePick::Count(10).indices(1000, 8));
        assert_eq!(BladePick::Count(5000).indices(30, 1).len(), 30);
        assert_eq!(BladePick::All.indices(4, 1), [0, 1, 2, 3]);
    }

    #[test]
    fn the_integral_length_of_a_straight_fall_is_its_triangle() {
        // 1 - r / 4 sampled every metre: the triangle under it, 2 m.
        assert!((integral_length(&[0.75, 0.5, 0.25, 0.0, -0.2], 1.0) - 2.0).abs() < 1e-12);
        // Crossing zero between samples: the line's own crossing.
        assert!((integral_length(&[0.5, -0.5], 2.0) - (1.5 + 0.25)).abs() < 1e-12);
        // Never reaching zero: what was sampled, a lower bound.
        assert!((integral_length(&[0.8, 0.6], 1.0) - 1.6).abs() < 1e-12);
    }

    /// Blades on a 1 m grid over 40 x 40 m whose tips follow `x_of(root,
    /// time)`, sampled at 10 Hz for 30 s.
    fn synthetic(x_of: impl Fn([f32; 2], f64) -> f32) -> Trace {
        let roots: Vec<[f32; 2]> = (0..40)
            .flat_map(|iz| (0..40).map(move |ix| [ix as f32 + 0.5, iz as f32 + 0.5]))
            .collect();
        let times: Vec<f64> = (0..300).map(|s| s as f64 * 0.1).collect();
        let tips = times
            .iter()
            .flat_map(|&t| roots.iter().map(move |&r| (r, t)))
            .map(|(r, t)| [r[0] + x_of(r, t), 0.3, r[1]])
            .collect();
        Trace {
            dt: 0.1,
            substeps: 1,
            blades: (0..roots.len() as u32).collect(),
            angles: vec![[0.0; 3]; times.len() * roots.len()],
            roots,
            times,
            tips,
            wind: Vec::new(),
            bend_hz: Vec::new(),
            swing_hz: Vec::new(),
            total_blades: 1600,
            steps_done: 300,
            interrupted: false,
        }
    }

    #[test]
    fn each_blade_ringing_at_its_own_frequency_peaks_at_one_when_scaled() {
        // Blades whose natural frequencies spread from 0.6 to 1.4 Hz, each
        // ringing at its own over a slow sway of 0.1 Hz: in hertz the
        // ringing is smeared over the spread, scaled it is one band.
        let mut run = synthetic(|r, t| {
            let natural = 0.6 + 0.02 * r[0] as f64;
            (0.01 * (std::f64::consts::TAU * natural * t).sin()
                + 0.02 * (std::f64::consts::TAU * 0.1 * t).sin()) as f32
        });
        run.bend_hz = run.roots.iter().map(|r| 0.6 + 0.02 * r[0] as f64).collect();
        let scaled = run.scaled_tip_spectrum(0.0).unwrap();
        assert_eq!(scaled.peak_over_natural, 1.0, "{scaled:?}");
        assert!(!scaled.peak_is_slowest_band);
        assert_eq!(scaled.blades, 1600);
        // Ringing alone: every blade's shares integrate to 1 over ln f
        // (Parseval), all bands being kept.
        let mut ringing = synthetic(|r, t| {
            let natural = 0.6 + 0.02 * r[0] as f64;
            (0.01 * (std::f64::consts::TAU * natural * t).sin()) as f32
        });
        ringing.bend_hz = run.bend_hz.clone();
        let scaled = ringing.scaled_tip_spectrum(0.0).unwrap();
        let step = std::f64::consts::LN_2 / 4.0;
        let total: f64 = scaled.power_per_log_f.iter().sum::<f64>() * step;
        assert!((total - 1.0).abs() < 0.1, "{total}");

        // A spectrum falling as f^-3 (f S(f) as f^-2) has its largest share
        // in its slowest band: no peak.
        let mut fall = synthetic(|r, t| {
            (1..=60)
                .map(|k| {
                    let phase = (k as f64 * 2.4 + r[0] as f64 * 0.7 + r[1] as f64 * 1.3).sin();
                    0.01 / (k as f64).powf(1.5)
                        * (std::f64::consts::TAU * k as f64 / 30.0 * t + 6.0 * phase).sin()
                })
                .sum::<f64>() as f32
        });
        fall.bend_hz = vec![0.9; fall.roots.len()];
        let scaled = fall.scaled_tip_spectrum(0.0).unwrap();
        assert!(scaled.peak_is_slowest_band, "{scaled:?}");
        // Blades that do not ring are left out.
        fall.bend_hz[0] = 0.0;
        assert_eq!(fall.scaled_tip_spectrum(0.0).unwrap().blades, 1599);
    }

    #[test]
    fn fronts_correlate_across_the_wind_and_noise_nowhere() {
        // A front: a wave 40 m long running along x, the same at every z.
        let front = synthetic(|r, t| {
            0.01 * (std::f64::consts::TAU * (r[0] as f64 - 3.0 * t) / 40.0).sin() as f32
        });
        let c = front.tip_correlation(0.0).unwrap();
        // About 1 blade a square metre: cells of about sqrt(20) m.
        assert!((4.0..4.6).contains(&c.cell_m), "{}", c.cell_m);
        // Along the wind, cos(2 pi r / 40): zero at 10 m, integral 40 / 2
        // pi (the trapezoids over cells 4.4 m wide come within 8% of it).
        let exact = 40.0 / std::f64::consts::TAU;
        assert!((c.along_length_m / exact - 1.0).abs() < 0.08, "{c:?}");
        // Across, the same motion everywhere: 1 at every separation.
        assert!(c.across.iter().all(|&r| r > 0.999), "{c:?}");
        assert!(c.bands_20m_across.unwrap() > 0.999);
        // Noise: every blade on its own (a hash of its root and the time).
        let noise = synthetic(|r, t| {
            let h = (r[0] * 12.9898 + r[1] * 78.233 + t as f32 * 37.719).sin() * 43_758.547;
            0.01 * (h - h.floor() - 0.5)
        });
        let c = noise.tip_correlation(0.0).unwrap();
        assert!(
            c.along.iter().chain(&c.across).all(|r| r.abs() < 0.2),
            "{c:?}"
        );
        assert!(c.bands_20m_across.unwrap().abs() < 0.3, "{c:?}");
        assert!(c.along_length_m < 0.7 * c.cell_m, "{c:?}");
    }

    #[test]
    fn a_straight_line_detrends_to_nothing_and_a_wave_keeps_its_shape() {
        let line: Vec<f64> = (0..50).map(|t| 3.0 + 0.2 * t as f64).collect();
        assert!(detrended(line).iter().all(|v| v.abs() < 1e-9));
        let wave: Vec<f64> = (0..100)
            .map(|t| (std::f64::consts::TAU * t as f64 / 20.0).sin())
            .collect();
        let with_trend: Vec<f64> = wave
            .iter()
            .enumerate()
            .map(|(t, v)| v + 0.05 * t as f64)
            .collect();
        let back = detrended(with_trend);
        let r = lagged_correlation(&back, &wave, 0);
        assert!(r > 0.98, "{r}");
    }

    #[test]
    fn blades_are_a_count_or_all() {
        assert_eq!(BladePick::parse("all").unwrap(), BladePick::All);
        assert_eq!(BladePick::parse("12").unwrap(), BladePick::Count(12));
        let e = BladePick::parse("0").unwrap_err().to_string();
        assert!(e.contains("--blades 0 is not allowed"), "{e}");
        assert!(BladePick::parse("some").is_err());
    }
}
