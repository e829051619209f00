//! Distance thinning on the CPU: the reference for glsl/common/thinning.glsl,
//! formula for formula. Beyond `from` metres only a share of the blades is
//! drawn, share(d) = clamp((from / d)^2, least, 1), so the blades drawn per
//! pixel stay the same as a blade's projected area falls as 1 / d^2; the
//! blades kept are widened by the inverse of the mean width profile (about
//! the inverse of the share) so the far meadow keeps its coverage. Each blade has a fixed random h in [0, 1): it is
//! drawn at full width while h < share(d) and narrows to nothing as h
//! crosses the band above it, so as the camera moves no blade pops.

use glam::Vec3;

use crate::scene::Scene;

/// The thinning of one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Thinning {
    /// Distance from the camera where it begins (m).
    pub from: f32,
    /// The least share of blades kept; 1 keeps every blade (thinning off).
    pub least: f32,
    /// Width of the narrowing band, as a share of the share kept.
    pub band: f32,
}

impl Thinning {
    /// Every blade at its own width.
    pub const OFF: Thinning = Thinning {
        from: 0.0,
        least: 1.0,
        band: 0.5,
    };

    /// The scene's: only with culling on, which leaves out the blades it
    /// drops, and a start distance above zero.
    pub fn of(scene: &Scene) -> Self {
        let c = &scene.cull;
        if c.enabled && c.thin_from > 0.0 && c.thin_least < 1.0 {
            Thinning {
                from: c.thin_from,
                least: c.thin_least,
                band: c.thin_band,
            }
        } else {
            Self::OFF
        }
    }

    pub fn is_on(&self) -> bool {
        self.least < 1.0
    }

    /// The share of blades drawn at squared distance `d2` from the camera,
    /// before the band.
    pub fn share(&self, d2: f32) -> f32 {
        (self.from * self.from / d2.max(1e-12)).clamp(self.least, 1.0)
    }

    /// The width scale of a blade rooted at `root` with colour variation
    /// `variation` (its `blade_rand`) seen from `eye`: 0 when thinned out.
    /// Also the margin the keep-or-drop decision was taken by (h's distance
    /// from the band's top, as a share), so a comparison with the GPU can
    /// tell rounding from a wrong answer.
    pub fn scale(&self, root: Vec3, variation: f32, eye: Vec3) -> (f32, f32) {
        let d2 = (root - eye).length_squared().max(1e-12);
        let h = blade_h(variation);
        let top = self.share(d2) * (1.0 + self.band);
        (self.scale_of_h(d2, h), (top - h).abs() / top)
    }

    /// The width scale of a blade with h = `h` at squared distance `d2`:
    /// full width below the share, narrowing to 0 over the band above it,
    /// divided by that profile's mean over h in [0, 1) (the band may reach
    /// past h = 1).
    pub fn scale_of_h(&self, d2: f32, h: f32) -> f32 {
        if !self.is_on() {
            return 1.0;
        }
        let share = self.share(d2);
        let band = self.band * share;
        let fade = ((share + band - h) / band).clamp(0.0, 1.0);
        let top = (share + band).min(1.0);
        let over = share + band - top;
        let mean = share + (band * band - over * over) / (2.0 * band);
        fade / mean
    }
}

/// The thinning's hash (`model::hash::lowbias32`), the same in
/// glsl/common/thinning.glsl.
pub use crate::model::hash::lowbias32 as hash;

/// A blade's h in [0, 1): 24 bits of the hash of its colour variation's
/// bits, exact in an f32.
pub fn blade_h(variation: f32) -> f32 {
    (hash(variation.to_bits()) >> 8) as f32 * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ON: Thinning = Thinning {
        from: 8.0,
        least: 0.125,
        band: 0.5,
    };

    /// The mean scale over `n` evenly spread h values at distance `d`,
    /// and the share of blades kept.
    fn over_h(t: &Thinning, d: f32, n: usize) -> (f64, f64) {
        let (mut sum, mut kept) = (0.0f64, 0usize);
        for i in 0..n {
            let h = (i as f32 + 0.5) / n as f32;
            let scale = t.scale_of_h(d * d, h);
            sum += scale as f64;
            kept += (scale > 0.0) as usize;
        }
        (sum / n as f64, kept as f64 / n as f64)
    }

    #[test]
    fn the_expected_width_is_the_unthinned_meadows_at_every_distance() {
        for d in [1.0, 7.9, 8.0, 9.0, 10.0, 12.0, 16.0, 22.6, 30.0, 100.0] {
            let (mean, kept) = over_h(&ON, d, 200_000);
            assert!((mean - 1.0).abs() < 1e-3, "d {d}: mean scale {mean}");
            let share = ON.share(d * d) as f64;
            let expect = (share * (1.0 + 0.5)).min(1.0);
            assert!((kept - expect).abs() < 1e-3, "d {d}: kept {kept}");
        }
        // Near the camera every blade is drawn at its own width.
        assert_eq!(ON.scale(Vec3::new(0.0, 0.0, 5.0), 0.37, Vec3::ZERO).0, 1.0);
    }

    #[test]
    fn far_blades_are_fewer_and_wider_and_none_pops() {
        let (_, kept_far) = over_h(&ON, 100.0, 100_000);
        assert!((kept_far - 0.1875).abs() < 1e-3, "{kept_far}");
        // One blade walked away from the camera in 1 mm steps: its scale
        // changes smoothly (the steepest change is the band's ramp) and it
        // reaches 0 without a jump.
        // A blade dropped within 20 m: h between 0.5 and 0.9.
        let variation = (1..1000)
            .map(|i| i as f32 / 1000.0)
            .find(|&v| (0.5..0.9).contains(&blade_h(v)))
            .unwrap();
        let h = blade_h(variation);
        let mut last = 1.0f32;
        let mut dropped_at = None;
        for i in 0..60_000 {
            let d = 2.0 + i as f32 * 0.001;
            let (s, _) = ON.scale(Vec3::new(0.0, 0.0, d), variation, Vec3::ZERO);
            assert!((s - last).abs() < 0.01, "jump {last} -> {s} at {d} m");
            if s == 0.0 && dropped_at.is_none() {
                dropped_at = Some(d);
            }
            last = s;
        }
        let d = dropped_at.expect("a blade with h above the least share is dropped");
        // It is dropped where share (1 + band) = h.
        let expect = ON.from / (h / 1.5).sqrt();
        assert!(
            (d - expect).abs() < 0.01,
            "dropped at {d}, expected {expect}"
        );
    }

    #[test]
    fn off_keeps_every_blade_at_its_width() {
        let mut scene = Scene::builtin("table1").unwrap();
        scene.cull.enabled = false;
        let t = Thinning::of(&scene);
        assert!(!t.is_on());
        for i in 0..1000 {
            let root = Vec3::new(0.0, 0.0, 0.1 * i as f32);
            assert_eq!(t.scale(root, i as f32 / 1000.0, Vec3::ZERO).0, 1.0);
        }
        scene.cull.enabled = true;
        assert!(Thinning::of(&scene).is_on());
        scene.cull.thin_from = 0.0;
        assert!(!Thinning::of(&scene).is_on());
    }

    #[test]
    fn h_is_uniform() {
        let mut bins = [0usize; 10];
        for i in 0..100_000u32 {
            let h = blade_h(i as f32 / 100_000.0);
            assert!((0.0..1.0).contains(&h));
            bins[(h * 10.0) as usize] += 1;
        }
        for b in bins {
            assert!((9_700..10_300).contains(&b), "{bins:?}");
        }
    }
}
