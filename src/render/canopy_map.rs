//! The canopy map: the leaf area index (one side's leaf area per square
//! metre of ground) of the scene's meadows and bunches over the ground,
//! made on the CPU at start-up, sampled by the fragment stages
//! (glsl/common/canopy.glsl): the blades are shaded by the leaf area above
//! them, and the ground under grass is the sward's floor, not soil. The
//! cover, which grows everywhere (or in its rectangle), is not in the map:
//! its leaf area index is a uniform (`cover_leaf_area_index`).

use crate::scene::Scene;

/// Texels along the map's longer side at most.
pub const MAP_TEXELS: u32 = 512;
/// The smallest texel (m): a bunch a few centimetres across still has
/// a few texels.
const LEAST_TEXEL_M: f32 = 0.01;

/// The cover's leaf area index (0 without one).
pub fn cover_leaf_area_index(scene: &Scene) -> f32 {
    scene
        .grass
        .cover
        .as_ref()
        .map_or(0.0, |c| c.density() * scene.grass.shape.mean_area())
}

/// The leaf area index on a grid of texels over the meadows and bunches.
#[derive(Clone, Debug, PartialEq)]
pub struct CanopyMap {
    pub width: u32,
    pub height: u32,
    /// World x, z of the map's least corner, and its extent (m).
    pub origin: [f32; 2],
    pub extent: [f32; 2],
    /// Row by row from the least z, each from the least x: where the grass
    /// grows, and how densely (the floor's cover).
    pub leaf_area_index: Vec<f32>,
    /// The same spread over about the canopy's height: the leaf area the
    /// light crosses on its way to a point. Beer-Lambert's law holds for a
    /// canopy wide against its height; light reaches into a tuft or a
    /// meadow's edge from the side, so a tuft a few centimetres across
    /// shades itself as its leaf area spread over a canopy's height does,
    /// not as a meadow of its density would.
    pub shade_leaf_area_index: Vec<f32>,
}

impl CanopyMap {
    /// The map of `scene`'s meadows (their masks thinning them) and
    /// bunches, with an empty texel all round (so a repeating sampler
    /// brings nothing in from the other side); one empty texel without
    /// them.
    pub fn of(scene: &Scene) -> Self {
        let mut lo = [f32::MAX; 2];
        let mut hi = [f32::MIN; 2];
        for p in scene.grass.patches() {
            let (c, h) = (p.center(), p.half_extent());
            for a in 0..2 {
                lo[a] = lo[a].min(c[a] - h[a]);
                hi[a] = hi[a].max(c[a] + h[a]);
            }
        }
        if lo[0] > hi[0] {
            return Self {
                width: 1,
                height: 1,
                origin: [0.0, 0.0],
                extent: [1.0, 1.0],
                leaf_area_index: vec![0.0],
                shade_leaf_area_index: vec![0.0],
            };
        }
        // The light's spread: the tallest blade's height, so the map
        // reaches that far beyond the grass.
        let spread = scene.grass.shape.height[1];
        for a in 0..2 {
            lo[a] -= spread;
            hi[a] += spread;
        }
        let span = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let texel = (span / (MAP_TEXELS - 2) as f32).max(LEAST_TEXEL_M);
        let texels = |a: usize| ((hi[a] - lo[a]) / texel).ceil() as u32 + 2;
        let (width, height) = (texels(0), texels(1));
        let origin = [lo[0] - texel, lo[1] - texel];
        let area = scene.grass.shape.mean_area();
        let mut lai = vec![0.0f32; (width * height) as usize];
        // Four samples a texel, so edges and small bunches are covered by
        // their share.
        const SUB: [f32; 2] = [0.25, 0.75];
        for j in 1..height - 1 {
            for i in 1..width - 1 {
                let mut sum = 0.0;
                for sz in SUB {
                    for sx in SUB {
                        let x = origin[0] + (i as f32 + sx) * texel;
                        let z = origin[1] + (j as f32 + sz) * texel;
                        sum += density_at(scene, x, z);
                    }
                }
                lai[(j * width + i) as usize] = 0.25 * sum * area;
            }
        }
        // Three box passes of half width spread / 2 each way: about a
        // Gaussian of that deviation, its border still empty.
        let half = ((0.5 * spread / texel).round() as usize).max(1);
        let mut shade = lai.clone();
        for _ in 0..3 {
            box_rows(&mut shade, width as usize, height as usize, half);
            transpose(&mut shade, width as usize, height as usize);
            box_rows(&mut shade, height as usize, width as usize, half);
            transpose(&mut shade, height as usize, width as usize);
        }
        for j in 0..height as usize {
            for i in 0..width as usize {
                if i == 0 || j == 0 || i + 1 == width as usize || j + 1 == height as usize {
                    shade[j * width as usize + i] = 0.0;
                }
            }
        }
        Self {
            width,
            height,
            origin,
            extent: [width as f32 * texel, height as f32 * texel],
            leaf_area_index: lai,
            shade_leaf_area_index: shade,
        }
    }

    /// The largest value: what the stored texels' 1.0 stands for (at
    /// least 1e-3, so an empty map divides by no zero).
    pub fn scale(&self) -> f32 {
        self.leaf_area_index.iter().copied().fold(1e-3, f32::max)
    }

    /// The texels as the GPU stores them: R8G8 UNORM of the leaf area
    /// index and its spread, over `scale`.
    pub fn texels(&self) -> Vec<u8> {
        let scale = self.scale();
        let byte = |v: f32| (v / scale * 255.0).round().clamp(0.0, 255.0) as u8;
        self.leaf_area_index
            .iter()
            .zip(&self.shade_leaf_area_index)
            .flat_map(|(&a, &b)| [byte(a), byte(b)])
            .collect()
    }

    /// `frame.canopy_map_min` and `canopy_map_inverse_extent` (glsl/common/frame.glsl): its least corner and
    /// one over its extent.
    pub fn placement(&self) -> ([f32; 2], [f32; 2]) {
        (self.origin, [1.0 / self.extent[0], 1.0 / self.extent[1]])
    }
}

/// Each row of `w` values replaced by its mean over `half` values either
/// side (the row's ends count as empty beyond it).
fn box_rows(values: &mut [f32], w: usize, h: usize, half: usize) {
    let mut row = vec![0.0f64; w + 1];
    for j in 0..h {
        let line = &mut values[j * w..(j + 1) * w];
        for i in 0..w {
            row[i + 1] = row[i] + line[i] as f64;
        }
        let n = (2 * half + 1) as f64;
        for (i, value) in line.iter_mut().enumerate() {
            let (a, b) = (i.saturating_sub(half), (i + half + 1).min(w));
            *value = ((row[b] - row[a]) / n) as f32;
        }
    }
}

/// `values` (h rows of w) as w rows of h.
fn transpose(values: &mut Vec<f32>, w: usize, h: usize) {
    let mut out = vec![0.0; values.len()];
    for j in 0..h {
        for i in 0..w {
            out[i * h + j] = values[j * w + i];
        }
    }
    *values = out;
}

/// Blades per square metre at (x, z): each meadow's over its rectangle
/// (times its mask), each bunch's over its disc, summed.
fn density_at(scene: &Scene, x: f32, z: f32) -> f32 {
    let meadows: f32 = scene
        .grass
        .meadow
        .iter()
        .filter(|m| {
            (x - m.center[0]).abs() <= 0.5 * m.size[0] && (z - m.center[1]).abs() <= 0.5 * m.size[1]
        })
        .map(|m| m.blades() as f32 / (m.size[0] * m.size[1]).max(1e-12) * m.mask_at(x, z))
        .sum();
    let bunches: f32 = scene
        .grass
        .bunch
        .iter()
        .filter(|b| (x - b.center[0]).hypot(z - b.center[1]) <= b.radius)
        .map(|b| b.count as f32 / (std::f32::consts::PI * b.radius * b.radius).max(1e-12))
        .sum();
    meadows + bunches
}

#[cfg(test)]
mod tests {
    use super::*;

    /// table1's meadow: 200,000 blades on 30 x 30 m of the default shapes,
    /// 0.55 m by 1.7 cm: leaf area index 222 x 0.55 x 0.017 x 2/3 = 1.39.
    #[test]
    fn a_meadow_s_leaf_area_index_is_its_density_times_a_blade_s_area() {
        let scene = Scene::builtin("table1").unwrap();
        let map = CanopyMap::of(&scene);
        let expected = 200_000.0 / 900.0 * 0.55 * 0.017 * (2.0 / 3.0);
        let at = |x: f32, z: f32| {
            let i = ((x - map.origin[0]) / map.extent[0] * map.width as f32) as u32;
            let j = ((z - map.origin[1]) / map.extent[1] * map.height as f32) as u32;
            map.leaf_area_index[(j * map.width + i) as usize]
        };
        assert!(
            (at(0.0, 0.0) - expected).abs() < 1e-3 * expected,
            "{}",
            at(0.0, 0.0)
        );
        assert!((map.scale() - expected).abs() < 1e-3 * expected);
        // Outside the meadow, and the border all round: none.
        assert_eq!(at(map.origin[0] + 0.01, 0.0), 0.0);
        assert_eq!(map.leaf_area_index[0], 0.0);
        assert_eq!(*map.leaf_area_index.last().unwrap(), 0.0);
        assert!(map.width <= MAP_TEXELS && map.height <= MAP_TEXELS);
        let texels = map.texels();
        assert_eq!(texels.len(), 2 * (map.width * map.height) as usize);
        assert_eq!(texels.iter().max(), Some(&255));
        // Spread over the canopy's height, the light's leaf area is the
        // meadow's inside it and falls off over its edge: half way at the
        // edge, a few percent at the map's end, a canopy's height beyond.
        let shade = |x: f32, z: f32| {
            let i = ((x - map.origin[0]) / map.extent[0] * map.width as f32) as u32;
            let j = ((z - map.origin[1]) / map.extent[1] * map.height as f32) as u32;
            map.shade_leaf_area_index[(j * map.width + i) as usize]
        };
        assert!((shade(0.0, 0.0) - expected).abs() < 1e-3 * expected);
        assert!(
            (shade(15.0, 0.0) / expected - 0.5).abs() < 0.05,
            "{}",
            shade(15.0, 0.0)
        );
        assert!(shade(15.74, 0.0) < 0.05 * expected, "{}", shade(15.74, 0.0));
        assert!(map.origin[0] + map.extent[0] < 15.9);
    }

    /// A mask's black path is bare in the map.
    #[test]
    fn a_mask_thins_the_map_where_it_thins_the_grass() {
        let scene = Scene::load("hills").unwrap();
        let meadow = scene.grass.meadow.iter().find(|m| m.mask_map.is_some());
        let Some(meadow) = meadow else {
            panic!("hills has a masked meadow");
        };
        let map = CanopyMap::of(&scene);
        let mut bare = 0;
        let mut full = 0;
        for j in 1..map.height - 1 {
            for i in 1..map.width - 1 {
                let x = map.origin[0] + (i as f32 + 0.5) * map.extent[0] / map.width as f32;
                let z = map.origin[1] + (j as f32 + 0.5) * map.extent[1] / map.height as f32;
                let inside = (x - meadow.center[0]).abs() < 0.5 * meadow.size[0] - 0.1
                    && (z - meadow.center[1]).abs() < 0.5 * meadow.size[1] - 0.1;
                if !inside {
                    continue;
                }
                let v = map.leaf_area_index[(j * map.width + i) as usize];
                if meadow.mask_at(x, z) < 0.01 {
                    assert!(v < 0.02 * map.scale(), "{v} at {x}, {z}");
                    bare += 1;
                } else if meadow.mask_at(x, z) > 0.99 {
                    full += 1;
                }
            }
        }
        assert!(bare > 100 && full > 1000, "{bare} {full}");
    }

    #[test]
    fn a_scene_with_only_a_cover_has_an_empty_map_and_the_cover_s_index() {
        let scene = Scene::builtin("steppe").unwrap();
        let map = CanopyMap::of(&scene);
        assert_eq!((map.width, map.height), (1, 1));
        assert_eq!(map.texels(), [0, 0]);
        let lai = cover_leaf_area_index(&scene);
        let density = scene.grass.cover.as_ref().unwrap().density();
        assert!(
            (lai - density * 0.55 * 0.017 * (2.0 / 3.0)).abs() < 1e-5,
            "{lai}"
        );
    }
}
