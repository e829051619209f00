//! The waves of light: whether the shaded picture shows the blades'
//! motion, as a person watching a meadow in gusts sees it (docs/physics.md,
//! "Waves of light").
//!
//! Each frame is cut into 16 x 16 pixel blocks. For a block, the shaded
//! frame gives its mean luminance (relative luminance of the linear
//! colour, Rec. 709 weights), and the data view of the same instant
//! (`VIEW_DISPLACEMENT`: glsl/blade/blade.frag) gives the share of its
//! pixels blades cover and the mean displacement of the blades it shows.
//! A block is grass when blades cover at least `LEAST_GRASS_SHARE` of it
//! in every frame. Over the frames, each block of grass has
//! - its modulation: the standard deviation of its luminance over its
//!   mean (a block that flickers by 5% of its brightness: 0.05);
//! - its correlation: Pearson's r of its luminance with its blades'
//!   displacement, frame by frame. Waves of light that follow the
//!   motion give |r| near 1; blades crossing pixels at random, near 0.
//!
//! The report gives the medians over the blocks.

use crate::analysis::stats::{lagged_correlation, mean, quantile, std_dev};
use crate::interface::DISPLACEMENT_FULL_SCALE;

/// A block's side in pixels.
pub const BLOCK_PIXELS: u32 = 16;
/// The least share of a block's pixels blades must cover, in every frame,
/// for it to count as grass.
pub const LEAST_GRASS_SHARE: f64 = 0.75;
/// Frames a measure needs at least.
pub const LEAST_FRAMES: usize = 3;

/// The waves of light over a run of frames (report.json's `light_waves`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LightWaves {
    /// The blocks' side in pixels.
    pub block_pixels: u32,
    /// Frames measured, and the simulated seconds from the first to the
    /// last (a gust period or more to see the waves).
    pub frames: usize,
    pub seconds: f64,
    /// The least share of a block blades cover in every frame for it to
    /// count, and the blocks that did, of all whole blocks.
    pub least_grass_share: f64,
    pub blocks: usize,
    pub blocks_in_frame: usize,
    /// Over the blocks of grass: the median, 25th and 75th percentile of
    /// the luminance's standard deviation over time over its mean (null
    /// without a block of grass).
    pub modulation_median: Option<f64>,
    pub modulation_p25: Option<f64>,
    pub modulation_p75: Option<f64>,
    /// The median of |r| and of r, r the correlation of a block's
    /// luminance with its blades' mean displacement over the frames.
    pub correlation_abs_median: Option<f64>,
    pub correlation_median: Option<f64>,
    /// The blades' displacement (rad) over the blocks of grass: its mean,
    /// and the median over blocks of its standard deviation over time.
    pub displacement_mean: Option<f64>,
    pub displacement_spread_median: Option<f64>,
}

/// Gathers the blocks' series frame by frame.
pub struct LightWaveSeries {
    width: u32,
    height: u32,
    times: Vec<f64>,
    /// Per block, per frame.
    luminance: Vec<Vec<f64>>,
    displacement: Vec<Vec<f64>>,
    /// Per block: the least share blades covered in any frame so far.
    least_cover: Vec<f64>,
}

impl LightWaveSeries {
    /// For frames of `width` x `height` pixels (the whole blocks only).
    pub fn new(width: u32, height: u32) -> Self {
        let blocks = ((width / BLOCK_PIXELS) * (height / BLOCK_PIXELS)) as usize;
        Self {
            width,
            height,
            times: Vec::new(),
            luminance: vec![Vec::new(); blocks],
            displacement: vec![Vec::new(); blocks],
            least_cover: vec![1.0; blocks],
        }
    }

    /// Adds the instant `time` (s): `shaded`, the picture, and `data`, the
    /// data view of the same instant, both RGBA8 sRGB-encoded rows top to
    /// bottom as read back.
    pub fn add(&mut self, time: f64, shaded: &[u8], data: &[u8]) {
        let pixels = (self.width * self.height) as usize;
        assert!(
            shaded.len() == 4 * pixels && data.len() == 4 * pixels,
            "light waves: frames of {} x {} pixels expected",
            self.width,
            self.height
        );
        let linear = srgb_to_linear_table();
        let blocks_x = self.width / BLOCK_PIXELS;
        let blocks_y = self.height / BLOCK_PIXELS;
        for by in 0..blocks_y {
            for bx in 0..blocks_x {
                let (mut lum, mut red, mut cover) = (0.0, 0.0, 0.0);
                for y in by * BLOCK_PIXELS..(by + 1) * BLOCK_PIXELS {
                    for x in bx * BLOCK_PIXELS..(bx + 1) * BLOCK_PIXELS {
                        let i = 4 * (y * self.width + x) as usize;
                        let [r, g, b] = [0, 1, 2].map(|c| linear[shaded[i + c] as usize]);
                        lum += 0.2126 * r + 0.7152 * g + 0.0722 * b;
                        red += linear[data[i] as usize];
                        cover += linear[data[i + 2] as usize];
                    }
                }
                let n = (BLOCK_PIXELS * BLOCK_PIXELS) as f64;
                let k = (by * blocks_x + bx) as usize;
                self.luminance[k].push(lum / n);
                // The resolve averages coverage-weighted samples: red is
                // the displacement times the blades' share of the pixel.
                let displacement = if cover > 0.0 {
                    DISPLACEMENT_FULL_SCALE as f64 * red / cover
                } else {
                    0.0
                };
                self.displacement[k].push(displacement);
                self.least_cover[k] = self.least_cover[k].min(cover / n);
            }
        }
        self.times.push(time);
    }

    /// The measure of the frames added; None before `LEAST_FRAMES`.
    pub fn measure(&self) -> Option<LightWaves> {
        if self.times.len() < LEAST_FRAMES {
            return None;
        }
        let grass: Vec<usize> = (0..self.least_cover.len())
            .filter(|&k| self.least_cover[k] >= LEAST_GRASS_SHARE)
            .collect();
        let mut modulation = Vec::with_capacity(grass.len());
        let mut correlation = Vec::with_capacity(grass.len());
        let mut spread = Vec::with_capacity(grass.len());
        let mut displacement = Vec::with_capacity(grass.len());
        for &k in &grass {
            let (lum, disp) = (&self.luminance[k], &self.displacement[k]);
            let m = mean(lum);
            modulation.push(if m > 0.0 { std_dev(lum) / m } else { 0.0 });
            correlation.push(lagged_correlation(lum, disp, 0));
            spread.push(std_dev(disp));
            displacement.push(mean(disp));
        }
        let abs: Vec<f64> = correlation.iter().map(|r| r.abs()).collect();
        Some(LightWaves {
            block_pixels: BLOCK_PIXELS,
            frames: self.times.len(),
            seconds: self.times.last().unwrap_or(&0.0) - self.times.first().unwrap_or(&0.0),
            least_grass_share: LEAST_GRASS_SHARE,
            blocks: grass.len(),
            blocks_in_frame: self.least_cover.len(),
            modulation_median: quantile(&modulation, 0.5),
            modulation_p25: quantile(&modulation, 0.25),
            modulation_p75: quantile(&modulation, 0.75),
            correlation_abs_median: quantile(&abs, 0.5),
            correlation_median: quantile(&correlation, 0.5),
            displacement_mean: (!displacement.is_empty()).then(|| mean(&displacement)),
            displacement_spread_median: quantile(&spread, 0.5),
        })
    }
}

/// The linear value of each sRGB-encoded byte.
fn srgb_to_linear_table() -> [f64; 256] {
    std::array::from_fn(|i| {
        let c = i as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    })
}

/// The sRGB byte of a linear value (0..=1), for tests and the data view's
/// reading.
pub fn linear_to_srgb(v: f64) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let c = if v <= 0.0031308 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (c * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A frame whose every pixel is `grey` (linear), and the data view with
    /// blades covering `cover` of each block's rows, displaced by `disp`.
    fn frames(
        w: u32,
        h: u32,
        grey: impl Fn(u32, u32) -> f64,
        disp: f64,
        cover: f64,
    ) -> (Vec<u8>, Vec<u8>) {
        let mut shaded = Vec::new();
        let mut data = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let g = linear_to_srgb(grey(x, y));
                shaded.extend([g, g, g, 255]);
                let covered = ((y % BLOCK_PIXELS) as f64) < cover * BLOCK_PIXELS as f64;
                if covered {
                    let red = linear_to_srgb(disp / DISPLACEMENT_FULL_SCALE as f64);
                    data.extend([red, 0, 255, 255]);
                } else {
                    data.extend([0, 0, 0, 255]);
                }
            }
        }
        (shaded, data)
    }

    /// Blocks whose brightness follows their blades' displacement by 10%
    /// of the mean: modulation 0.1 / sqrt(2) for a sine, r = 1.
    #[test]
    fn a_picture_that_follows_the_motion_measures_its_modulation_and_correlation() {
        let (w, h) = (64, 32);
        let mut series = LightWaveSeries::new(w, h);
        for f in 0..40 {
            let phase = (f as f64 * 0.4).sin();
            let disp = 0.4 + 0.2 * phase;
            let (shaded, data) = frames(w, h, |_, _| 0.2 * (1.0 + 0.1 * phase), disp, 1.0);
            series.add(f as f64 * 0.125, &shaded, &data);
        }
        let m = series.measure().unwrap();
        assert_eq!((m.blocks, m.blocks_in_frame, m.frames), (8, 8, 40));
        let phase: Vec<f64> = (0..40).map(|f| (f as f64 * 0.4).sin()).collect();
        let light: Vec<f64> = phase.iter().map(|p| 1.0 + 0.1 * p).collect();
        let expected = std_dev(&light) / mean(&light);
        let modulation = m.modulation_median.unwrap();
        // The bytes' rounding: a few parts in a thousand of the light.
        assert!(
            (modulation - expected).abs() < 0.03 * expected,
            "{modulation} vs {expected}"
        );
        assert!(m.correlation_abs_median.unwrap() > 0.99, "{m:?}");
        assert!(m.correlation_median.unwrap() > 0.99);
        let displacement = 0.4 + 0.2 * mean(&phase);
        assert!(
            (m.displacement_mean.unwrap() - displacement).abs() < 0.01,
            "{m:?}"
        );
        assert!((m.seconds - 39.0 * 0.125).abs() < 1e-12);
    }

    /// Brightness that flickers at random beside a steady sway: some
    /// modulation, little correlation.
    #[test]
    fn flicker_unrelated_to_the_motion_does_not_correlate() {
        let (w, h) = (64, 32);
        let mut series = LightWaveSeries::new(w, h);
        let mut state = 12345u64;
        for f in 0..64 {
            let disp = 0.4 + 0.2 * (f as f64 * 0.4).sin();
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = (state >> 33) as f64 / (1u64 << 31) as f64 - 0.5;
            let (shaded, data) = frames(w, h, |_, _| 0.2 * (1.0 + 0.1 * noise), disp, 1.0);
            series.add(f as f64, &shaded, &data);
        }
        let m = series.measure().unwrap();
        assert!(m.modulation_median.unwrap() > 0.02, "{m:?}");
        assert!(m.correlation_abs_median.unwrap() < 0.35, "{m:?}");
    }

    /// Blocks half covered are not grass; too few frames, no measure.
    #[test]
    fn blocks_of_soil_and_short_runs_are_left_out() {
        let (w, h) = (32, 16);
        let mut series = LightWaveSeries::new(w, h);
        for f in 0..2 {
            let (shaded, data) = frames(w, h, |_, _| 0.3, 0.2, 0.5);
            series.add(f as f64, &shaded, &data);
        }
        assert!(series.measure().is_none());
        let (shaded, data) = frames(w, h, |_, _| 0.3, 0.2, 0.5);
        series.add(2.0, &shaded, &data);
        let m = series.measure().unwrap();
        assert_eq!((m.blocks, m.blocks_in_frame), (0, 2));
        assert_eq!(m.modulation_median, None);
        // The displacement reads back from half-covered pixels too.
        let mut one = LightWaveSeries::new(16, 16);
        for f in 0..3 {
            let (shaded, data) = frames(16, 16, |_, _| 0.3, 0.3, 0.8);
            one.add(f as f64, &shaded, &data);
        }
        let m = one.measure().unwrap();
        assert_eq!(m.blocks, 1);
        assert!((m.displacement_mean.unwrap() - 0.3).abs() < 0.01, "{m:?}");
    }
}
