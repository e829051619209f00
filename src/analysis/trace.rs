//! A trace's analysis (`meadow trace`'s and the tests'): the traced
//! blades' tips and wind over time (`Trace`, filled by
//! `commands::trace` on the GPU or on the CPU reference), and what is
//! measured of them: each band's or cell's mean displacement, the tips'
//! spectra (in hertz, and per unit log frequency against each blade's
//! own natural frequency), the blades' natural frequencies' spread and
//! the tips' correlation across the field. Plain arithmetic: no GPU, no
//! files; it uses `analysis::stats`.

use std::collections::BTreeMap;

use crate::analysis::stats::lagged_correlation;

/// The frame a trace is measured in: `downwind`, the unit (x, z) the mean
/// wind blows along (the inflow's heading, or x without an inflow), and
/// across it. Downwind displacement, bands, cells and correlations along
/// and across the wind are read in it; at (1, 0) its coordinates are the
/// world's x and z bit for bit.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct WindFrame {
    pub downwind: [f32; 2],
}

impl Default for WindFrame {
    fn default() -> Self {
        Self {
            downwind: [1.0, 0.0],
        }
    }
}

impl WindFrame {
    /// How far along the wind (x, z) lies.
    pub fn along(&self, p: [f32; 2]) -> f32 {
        p[0] * self.downwind[0] + p[1] * self.downwind[1]
    }

    /// How far across it (x, z) lies: z at downwind (1, 0).
    pub fn across(&self, p: [f32; 2]) -> f32 {
        p[1] * self.downwind[0] - p[0] * self.downwind[1]
    }

    /// (along, across) of (x, z).
    pub fn of(&self, p: [f32; 2]) -> [f32; 2] {
        [self.along(p), self.across(p)]
    }

    /// The axes' names for a diagram: the world's where they are its x
    /// and z.
    pub fn axis_names(&self) -> (String, String) {
        if self.downwind == [1.0, 0.0] {
            ("x, along the wind (m)".into(), "z (m)".into())
        } else {
            let heading = self.downwind[1].atan2(self.downwind[0]).to_degrees();
            (
                format!("along the wind, heading {heading:.0} deg (m)"),
                "across the wind (m)".into(),
            )
        }
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
    /// Along and across the wind.
    pub frame: WindFrame,
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

    /// How far along the wind blade b's tip is at sample s.
    pub fn tip_along(&self, sample: usize, blade: usize) -> f32 {
        let tip = self.tip(sample, blade);
        self.frame.along([tip[0], tip[2]])
    }

    /// Each traced blade's root along and across the wind.
    pub fn roots_in_frame(&self) -> impl Iterator<Item = [f32; 2]> + '_ {
        self.roots.iter().map(|&r| self.frame.of(r))
    }
}

impl Trace {
    /// The mean downwind tip displacement (the tip's distance along the
    /// wind now less at the first sample) of the traced blades rooted in
    /// each band of `band_width` metres along the wind from `x0` (a
    /// `WindFrame` coordinate), per sample: `[band][sample]`.
    /// A band without blades is all zeros.
    pub fn band_displacement(&self, x0: f32, band_width: f32, bands: usize) -> Vec<Vec<f64>> {
        self.grouped_displacement(bands, |root| {
            let band = ((root[0] - x0) / band_width).floor();
            (0.0..bands as f32).contains(&band).then_some(band as usize)
        })
    }

    /// As `band_displacement`, over square cells of `cell` metres from
    /// `corner` (along, across the wind), `nx` along the wind and `nz`
    /// across it: `[iz * nx + ix][sample]`.
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

    /// Cells (or bands) whose traced blades share no group are all zeros;
    /// `group_of` takes a root along and across the wind.
    fn grouped_displacement(
        &self,
        groups: usize,
        group_of: impl Fn([f32; 2]) -> Option<usize>,
    ) -> Vec<Vec<f64>> {
        let mut sum = vec![vec![0.0f64; self.times.len()]; groups];
        let mut count = vec![0usize; groups];
        for (b, root) in self.roots_in_frame().enumerate() {
            let Some(group) = group_of(root) else {
                continue;
            };
            count[group] += 1;
            let rest = self.tip_along(0, b);
            for (s, total) in sum[group].iter_mut().enumerate() {
                *total += (self.tip_along(s, b) - rest) as f64;
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
    /// The spectrum of the tips' motion along the wind from `from_s` on: each
    /// traced blade's periodogram, averaged over the blades. None with
    /// fewer than 8 samples after `from_s`.
    pub fn tip_spectrum(&self, from_s: f64) -> Option<Spectrum> {
        self.mean_spectrum(from_s, |s, b| self.tip_along(s, b) as f64)
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
                .map(|s| self.tip_along(s, b) as f64)
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

/// The traced blades' roots in square cells along and across the wind
/// (`WindFrame`; x and z at heading 0): where the plan view and the tips'
/// correlation look.
pub struct CellGrid {
    pub corner: [f32; 2],
    pub cell: f32,
    pub nx: usize,
    pub nz: usize,
    /// Whether each cell (`iz * nx + ix`) holds a traced blade.
    pub filled: Vec<bool>,
}

impl CellGrid {
    /// Cells of 2 m, or larger so that there are at most 40 along a side
    /// and about 20 traced blades in a cell on average. None without
    /// blades.
    pub fn of(run: &Trace) -> Option<Self> {
        if run.roots.is_empty() {
            return None;
        }
        let fold = |i: usize| {
            run.roots_in_frame()
                .fold((f32::MAX, f32::MIN), |(lo, hi), r| {
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
        for r in run.roots_in_frame() {
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
    pub fn displacement(&self, run: &Trace, skip: usize) -> Vec<Vec<f64>> {
        run.cell_displacement(self.corner, self.cell, self.nx, self.nz)
            .into_iter()
            .map(|c| c[skip..].to_vec())
            .collect()
    }
}

/// How far the tips' motion stays alike across the field: the mean
/// correlation (lag 0) of the downwind tip displacement of two cells
/// (`CellGrid`) at each separation along the wind and across it (the
/// trace's `WindFrame`), their integral lengths,
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
            frame: WindFrame::default(),
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

    /// The same front under a wind along z (heading 90), its tips moving
    /// along z: read in the wind's frame it correlates as the front along
    /// x does at heading 0, where x would see no motion at all.
    #[test]
    fn a_front_under_a_wind_along_z_reads_as_one_along_x() {
        let wave = |along: f32, t: f64| {
            0.01 * (std::f64::consts::TAU * (along as f64 - 3.0 * t) / 40.0).sin() as f32
        };
        let east = synthetic(|r, t| wave(r[0], t));
        let mut north = synthetic(|_, _| 0.0);
        for (s, &t) in north.times.clone().iter().enumerate() {
            for (b, r) in north.roots.clone().iter().enumerate() {
                north.tips[s * north.blades.len() + b][2] += wave(r[1], t);
            }
        }
        north.frame = WindFrame {
            downwind: [0.0, 1.0],
        };
        let (e, n) = (
            east.tip_correlation(0.0).unwrap(),
            north.tip_correlation(0.0).unwrap(),
        );
        assert!(
            (n.along_length_m / e.along_length_m - 1.0).abs() < 1e-3,
            "{n:?}"
        );
        assert!(n.across.iter().all(|&r| r > 0.999), "{n:?}");
        let (pe, pn) = (
            east.tip_spectrum(0.0).unwrap(),
            north.tip_spectrum(0.0).unwrap(),
        );
        assert!((pn.peak_hz - pe.peak_hz).abs() < 1e-9 && pn.power[1] > 0.0);
        north.frame = WindFrame::default();
        assert!(north
            .tip_spectrum(0.0)
            .unwrap()
            .power
            .iter()
            .all(|&p| p == 0.0));
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
}
