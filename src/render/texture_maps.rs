//! The pictures on the surfaces, made at start-up: the grass texture laid
//! along every blade (paper section 5: "a grass texture is mapped onto the
//! blade") and the soil under it, each with its whole mip chain. Pure CPU
//! and deterministic (a fixed integer hash, no random state), so a frame
//! depends on nothing but the scene and seed.
//!
//! Both are sRGB-encoded RGBA8 (alpha 255: a blade's outline is its
//! geometry, not an alpha mask, so no alpha-to-coverage is needed). Mips are
//! averaged in linear light, as the GPU filters them.

use image::{Rgba, RgbaImage};

/// Across the blade (u) x along it (v, root at row 0).
pub const GRASS_SIZE: (u32, u32) = (64, 256);
/// One tile of soil, repeated every `GROUND_TILE_M` metres.
pub const GROUND_SIZE: u32 = 256;
pub const GROUND_TILE_M: f32 = 2.0;

/// A blade's texture: the average blade of the meadow (the fragment shader
/// tints each blade a little by its random number). Dark and cool at the
/// root, light and warmer toward the tip, drying at the very tip; a
/// lighter midrib, parallel veins, darker edges and fine streaks.
pub fn grass_texture() -> RgbaImage {
    let (w, h) = GRASS_SIZE;
    RgbaImage::from_fn(w, h, |x, y| {
        let u = (x as f32 + 0.5) / w as f32;
        let v = (y as f32 + 0.5) / h as f32;
        let root = [0.035, 0.090, 0.012];
        let middle = [0.115, 0.290, 0.035];
        let tip = [0.290, 0.440, 0.075];
        let dry = [0.420, 0.400, 0.130];
        let mut c = if v < 0.5 {
            mix3(root, middle, smoothstep(0.0, 0.5, v))
        } else {
            mix3(middle, tip, smoothstep(0.5, 1.0, v))
        };
        c = mix3(c, dry, smoothstep(0.90, 1.0, v) * 0.6);
        let across = (u - 0.5).abs() * 2.0; // 0 on the midrib, 1 at the edge
        let midrib = 1.0 + 0.18 * (1.0 - smoothstep(0.0, 0.08, across));
        let veins = 0.93 + 0.07 * (across * std::f32::consts::PI * 6.0).cos();
        let edge = 1.0 - 0.18 * smoothstep(0.75, 1.0, across);
        // Streaks run along the blade: noise that changes fast across it
        // and slowly along it.
        let streak = 0.94 + 0.12 * value_noise(u * 24.0, v * 6.0, 7, 0);
        let k = midrib * veins * edge * streak;
        encode([c[0] * k, c[1] * k, c[2] * k])
    })
}

/// Soil: fractal noise between dry and damp earth, dark humus patches and a
/// few light pebbles. Tiles seamlessly (every noise period divides the
/// tile).
pub fn ground_texture() -> RgbaImage {
    let n = GROUND_SIZE;
    RgbaImage::from_fn(n, n, |x, y| {
        let s = (x as f32 + 0.5) / n as f32;
        let t = (y as f32 + 0.5) / n as f32;
        let mut f = 0.0;
        let mut amplitude = 0.5;
        for (octave, period) in [4u32, 8, 16, 32, 64].into_iter().enumerate() {
            f += amplitude
                * value_noise(s * period as f32, t * period as f32, period, octave as u32);
            amplitude *= 0.55;
        }
        let damp = [0.070, 0.046, 0.024];
        let dry = [0.150, 0.115, 0.060];
        let mut c = mix3(damp, dry, smoothstep(0.25, 0.75, f));
        let humus = smoothstep(0.55, 0.75, value_noise(s * 6.0, t * 6.0, 6, 11));
        c = mix3(c, [0.040, 0.030, 0.018], humus * 0.7);
        // Pebbles: about one cell in twenty of a 48 x 48 lattice holds one,
        // a soft disc at a hashed place in the cell.
        let (gx, gy) = (s * 48.0, t * 48.0);
        let (cx, cy) = (gx.floor() as u32 % 48, gy.floor() as u32 % 48);
        let h = hash(cx, cy, 23);
        if h % 20 == 0 {
            let px = ((h >> 8) & 0xff) as f32 / 255.0 * 0.5 + 0.25;
            let py = ((h >> 16) & 0xff) as f32 / 255.0 * 0.5 + 0.25;
            let d = ((gx.fract() - px).powi(2) + (gy.fract() - py).powi(2)).sqrt();
            let pebble = 1.0 - smoothstep(0.12, 0.22, d);
            c = mix3(c, [0.17, 0.15, 0.12], pebble * 0.6);
        }
        encode(c)
    })
}

/// The full mip chain of `base`, level 0 first, down to 1 x 1. Each level
/// is the 2 x 2 box average of the one above, in linear light (a side that
/// is already 1 stays 1). Sides must be powers of two.
pub fn mip_chain(base: RgbaImage) -> Vec<RgbaImage> {
    assert!(
        base.width().is_power_of_two() && base.height().is_power_of_two(),
        "texture sides must be powers of two"
    );
    let mut chain = vec![base];
    loop {
        let last = chain.last().unwrap();
        let (w, h) = last.dimensions();
        if w == 1 && h == 1 {
            return chain;
        }
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let next = RgbaImage::from_fn(nw, nh, |x, y| {
            let mut sum = [0.0f32; 4];
            let xs = if w > 1 { [2 * x, 2 * x + 1] } else { [0, 0] };
            let ys = if h > 1 { [2 * y, 2 * y + 1] } else { [0, 0] };
            for sy in ys {
                for sx in xs {
                    let p = last.get_pixel(sx, sy).0;
                    for c in 0..3 {
                        sum[c] += srgb_to_linear(p[c]);
                    }
                    sum[3] += p[3] as f32 / 255.0;
                }
            }
            let mut e = encode([sum[0] / 4.0, sum[1] / 4.0, sum[2] / 4.0]);
            e.0[3] = (sum[3] / 4.0 * 255.0).round() as u8;
            e
        });
        chain.push(next);
    }
}

/// Number of levels in a full chain for a `w` x `h` base.
pub fn mip_levels(w: u32, h: u32) -> u32 {
    32 - w.max(h).leading_zeros()
}

pub fn srgb_to_linear(c: u8) -> f32 {
    let c = c as f32 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

pub fn linear_to_srgb(l: f32) -> u8 {
    let l = l.clamp(0.0, 1.0);
    let c = if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (c * 255.0).round() as u8
}

fn encode(c: [f32; 3]) -> Rgba<u8> {
    Rgba([
        linear_to_srgb(c[0]),
        linear_to_srgb(c[1]),
        linear_to_srgb(c[2]),
        255,
    ])
}

fn mix3(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
    ]
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// A 32-bit integer hash (lowbias32 by Chris Wellons) of a lattice point.
fn hash(x: u32, y: u32, salt: u32) -> u32 {
    let mut h = x
        .wrapping_mul(0x9e37_79b1)
        .wrapping_add(y.wrapping_mul(0x85eb_ca77))
        .wrapping_add(salt.wrapping_mul(0xc2b2_ae3d));
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    h
}

/// Smooth value noise in 0..1 on a lattice that repeats every `period`
/// cells in both directions.
fn value_noise(x: f32, y: f32, period: u32, salt: u32) -> f32 {
    let (ix, iy) = (x.floor(), y.floor());
    let (fx, fy) = (x - ix, y - iy);
    let (ux, uy) = (fx * fx * (3.0 - 2.0 * fx), fy * fy * (3.0 - 2.0 * fy));
    let cell = |dx: i64, dy: i64| {
        let cx = (ix as i64 + dx).rem_euclid(period as i64) as u32;
        let cy = (iy as i64 + dy).rem_euclid(period as i64) as u32;
        hash(cx, cy, salt) as f32 / u32::MAX as f32
    };
    let a = cell(0, 0) + (cell(1, 0) - cell(0, 0)) * ux;
    let b = cell(0, 1) + (cell(1, 1) - cell(0, 1)) * ux;
    a + (b - a) * uy
}

#[cfg(test)]
mod tests {
    use super::*;

    fn linear_mean(img: &RgbaImage) -> [f32; 3] {
        let mut m = [0.0f64; 3];
        for p in img.pixels() {
            for (sum, &c) in m.iter_mut().zip(&p.0[..3]) {
                *sum += srgb_to_linear(c) as f64;
            }
        }
        let n = (img.width() * img.height()) as f64;
        [(m[0] / n) as f32, (m[1] / n) as f32, (m[2] / n) as f32]
    }

    #[test]
    fn chains_run_down_to_one_texel_and_keep_the_mean() {
        for base in [grass_texture(), ground_texture()] {
            let (w, h) = base.dimensions();
            let mean = linear_mean(&base);
            let chain = mip_chain(base);
            assert_eq!(chain.len() as u32, mip_levels(w, h));
            for (i, level) in chain.iter().enumerate() {
                assert_eq!(level.width(), (w >> i).max(1));
                assert_eq!(level.height(), (h >> i).max(1));
            }
            let last = chain.last().unwrap();
            assert_eq!(last.dimensions(), (1, 1));
            // Each level rounds to 8 bits; the mean drifts by at most about
            // one sRGB step per level.
            let top = linear_mean(last);
            for c in 0..3 {
                let tol = mean[c] * 0.05 + 2e-3;
                assert!(
                    (top[c] - mean[c]).abs() < tol,
                    "channel {c}: {top:?} vs {mean:?}"
                );
            }
        }
    }

    #[test]
    fn the_blade_lightens_from_root_to_tip() {
        let img = grass_texture();
        let row_luma = |y: u32| {
            (0..img.width())
                .map(|x| srgb_to_linear(img.get_pixel(x, y).0[1]))
                .sum::<f32>()
        };
        let (h4, h) = (img.height() / 4, img.height());
        assert!(row_luma(0) < row_luma(h4));
        assert!(row_luma(h4) < row_luma(2 * h4));
        assert!(row_luma(2 * h4) < row_luma(h - h4));
        // Both halves of the blade are mirror images (the midrib in the middle).
        let (w, y) = (img.width(), h / 2);
        for x in 0..w / 2 {
            let a = img.get_pixel(x, y).0;
            let b = img.get_pixel(w - 1 - x, y).0;
            for c in 0..3 {
                assert!((a[c] as i32 - b[c] as i32).abs() <= 40, "{x}: {a:?} {b:?}");
            }
        }
    }

    #[test]
    fn the_soil_tiles_without_a_seam() {
        let img = ground_texture();
        let n = img.width();
        // The jump across the tile's edge is no larger than jumps inside it.
        let diff = |a: &Rgba<u8>, b: &Rgba<u8>| {
            (0..3)
                .map(|c| (a.0[c] as i32 - b.0[c] as i32).abs())
                .sum::<i32>()
        };
        let mut across_edge = 0;
        let mut inside = 0;
        for y in 0..n {
            across_edge += diff(img.get_pixel(n - 1, y), img.get_pixel(0, y));
            inside += diff(img.get_pixel(n / 2 - 1, y), img.get_pixel(n / 2, y));
        }
        assert!(
            (across_edge as f32) < inside as f32 * 1.5 + n as f32,
            "edge {across_edge} vs inside {inside}"
        );
    }

    #[test]
    fn same_pictures_every_time() {
        assert_eq!(grass_texture().as_raw(), grass_texture().as_raw());
        assert_eq!(ground_texture().as_raw(), ground_texture().as_raw());
    }

    #[test]
    fn srgb_round_trips() {
        for c in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(c)), c);
        }
    }
}
