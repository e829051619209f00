//! The ground's height field (ours; the paper's meadow is flat): h(x, z),
//! the sum of a sampled height map and features a scene writes by hand,
//! hills and ridges with the Witch-of-Agnesi profile H / (1 + (d/L)^2),
//! the classic obstacle of flow-over-hills theory, whose linear potential
//! flow has a closed form (docs/physics.md, wind over a ridge).
//!
//! Flat (no map, no feature) is h = 0 everywhere: every path that asks a
//! flat terrain for a height gets exactly 0.0, so flat scenes are
//! unchanged bit for bit.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::Blade;
use crate::interface::TerrainHeader;

/// The central differences a root's ground normal is taken over (m): its
/// tangent plane, for contact's paraboloid over it (`Terrain::grounded`) and
/// the cover's fit (glsl/common/terrain.glsl's `terrain_normal` alike).
pub use crate::interface::TERRAIN_NORMAL_STEP_M as NORMAL_STEP_M;

/// A round hill: H / (1 + (r/L)^2), r the distance from `center` (x, z).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hill {
    pub center: [f32; 2],
    /// H (m); negative digs a hollow.
    pub height: f32,
    /// L (m): the distance at which the height is H / 2.
    pub half_width: f32,
}

/// A ridge: H / (1 + (d/L)^2), d the distance across its long axis,
/// which passes through `center` along `heading` (degrees; 0 along +x,
/// 90 along +z).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ridge {
    pub center: [f32; 2],
    pub height: f32,
    pub half_width: f32,
    #[serde(default)]
    pub heading: f32,
}

/// A height map: `columns` x `rows` samples in metres, row-major (x
/// fastest), spread over `extent` (x, z metres) centred at `center`; sample
/// (0, 0) at the minimum corner, the last at the maximum; bilinear between
/// samples, and held at the edge's value beyond it.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    pub columns: u32,
    pub rows: u32,
    pub heights: Vec<f32>,
    pub extent: [f32; 2],
    pub center: [f32; 2],
}

impl HeightMap {
    pub fn height(&self, x: f32, z: f32) -> f32 {
        let (u, v) = (
            (x - self.center[0]) / self.extent[0] + 0.5,
            (z - self.center[1]) / self.extent[1] + 0.5,
        );
        bilinear(&self.heights, self.columns, self.rows, u, v)
    }

    pub fn range(&self) -> (f32, f32) {
        self.heights
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), &h| (lo.min(h), hi.max(h)))
    }
}

/// Bilinear sample of a `columns` x `rows` grid of `values` (row-major,
/// x fastest) at (u, v), 0 at the first sample and 1 at the last along
/// each axis, held at the edges' values beyond them: a height map, a
/// meadow's density mask.
pub fn bilinear(values: &[f32], columns: u32, rows: u32, u: f32, v: f32) -> f32 {
    let (nx, nz) = (columns as f32, rows as f32);
    let u = (u * (nx - 1.0)).clamp(0.0, nx - 1.0);
    let v = (v * (nz - 1.0)).clamp(0.0, nz - 1.0);
    let (i0, j0) = (u.floor() as u32, v.floor() as u32);
    let (i1, j1) = ((i0 + 1).min(columns - 1), (j0 + 1).min(rows - 1));
    let (fu, fv) = (u - i0 as f32, v - j0 as f32);
    let at = |i: u32, j: u32| values[(i + columns * j) as usize];
    let a = at(i0, j0) * (1.0 - fu) + at(i1, j0) * fu;
    let b = at(i0, j1) * (1.0 - fu) + at(i1, j1) * fu;
    a * (1.0 - fv) + b * fv
}

/// The ground: h(x, z) in metres, y up.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Terrain {
    pub map: Option<Arc<HeightMap>>,
    pub hills: Vec<Hill>,
    pub ridges: Vec<Ridge>,
}

/// H / (1 + (d/L)^2).
fn agnesi(height: f32, half_width: f32, distance_squared: f32) -> f32 {
    height / (1.0 + distance_squared / (half_width * half_width))
}

impl Terrain {
    pub fn is_flat(&self) -> bool {
        self.map.is_none() && self.hills.is_empty() && self.ridges.is_empty()
    }

    /// An upper bound of the ground's slope |grad h| anywhere: each hill's
    /// and ridge's steepest, 3 sqrt(3) / 8 |H| / L (at d = L / sqrt(3)),
    /// summed with the height map's (a bilinear patch is no steeper along
    /// an axis than its steepest sample step that way), a thousandth over
    /// for rounding; 0 where the terrain is flat.
    pub fn max_slope(&self) -> f32 {
        let agnesi = |height: f32, half_width: f32| 0.649_519 * height.abs() / half_width;
        let features: f32 = self
            .hills
            .iter()
            .map(|h| agnesi(h.height, h.half_width))
            .chain(self.ridges.iter().map(|r| agnesi(r.height, r.half_width)))
            .sum();
        let map = self.map.as_deref().map_or(0.0, |m| {
            let (columns, rows) = (m.columns as usize, m.rows as usize);
            let at = |i: usize, j: usize| m.heights[i + columns * j];
            let steepest = |steps: &mut dyn Iterator<Item = f32>| steps.fold(0f32, f32::max);
            let along_x = steepest(
                &mut (0..rows)
                    .flat_map(|j| (1..columns).map(move |i| (at(i, j) - at(i - 1, j)).abs())),
            );
            let along_z = steepest(
                &mut (1..rows)
                    .flat_map(|j| (0..columns).map(move |i| (at(i, j) - at(i, j - 1)).abs())),
            );
            let cell = |extent: f32, n: usize| extent / (n.max(2) - 1) as f32;
            (along_x / cell(m.extent[0], columns)).hypot(along_z / cell(m.extent[1], rows))
        });
        (features + map) * 1.001
    }

    /// The ground's height at (x, z); exactly 0 where the terrain is flat.
    pub fn height(&self, x: f32, z: f32) -> f32 {
        if self.is_flat() {
            return 0.0;
        }
        let p = Vec2::new(x, z);
        let mut h = self.map.as_ref().map_or(0.0, |m| m.height(x, z));
        for hill in &self.hills {
            let r2 = p.distance_squared(Vec2::from(hill.center));
            h += agnesi(hill.height, hill.half_width, r2);
        }
        for ridge in &self.ridges {
            let (s, c) = ridge.heading.to_radians().sin_cos();
            // Distance across the axis (c, s) through the centre.
            let d = (p - Vec2::from(ridge.center)).perp_dot(Vec2::new(c, s));
            h += agnesi(ridge.height, ridge.half_width, d * d);
        }
        h
    }

    /// `blade` (made on flat ground) rooted on the ground, raised to the
    /// height under its root, growing upright as grass does on a slope,
    /// with contact's paraboloid over the ground within its reach
    /// (`lifted`, then `grounded`), its rest shape then fitted to the
    /// ground (`Blade::fitted`: a blade leaning or drooping into a slope
    /// turned away from it), so that no point of it is under the ground at
    /// rest. The patches'
    /// blades are; the cover's, whose tile kernel cannot afford the
    /// ground's rise for every blade every frame, are fitted to the
    /// ground's heights under their curves (`scene::cover::fitted`).
    pub fn root_fitted(&self, blade: Blade) -> Blade {
        if self.is_flat() {
            return blade;
        }
        let (rooted, rise) = self.rooted(blade);
        rooted.fitted(rise)
    }

    /// `blade` lifted and grounded, and the ground's rise bound c there.
    fn rooted(&self, blade: Blade) -> (Blade, f32) {
        self.grounded_with_rise(self.lifted(blade))
    }

    /// `blade` (made on flat ground) raised by the ground's height under
    /// its root, each rest point's y plus that height as the cover's tile
    /// kernel adds it; its frame and contact as they were.
    pub fn lifted(&self, blade: Blade) -> Blade {
        if self.is_flat() {
            return blade;
        }
        let root = blade.rest[0];
        let lift = self.height(root.x, root.z);
        Blade {
            rest: blade.rest.map(|p| Vec3::new(p.x, p.y + lift, p.z)),
            ..blade
        }
    }

    /// `blade`, its root already on the ground (`lifted`), swinging about
    /// the ground's normal at its root, with contact's paraboloid over the
    /// ground within its reach (`Blade::raised` by nothing).
    pub fn grounded(&self, blade: Blade) -> Blade {
        self.grounded_with_rise(blade).0
    }

    /// `grounded`, and the ground's rise bound c there.
    fn grounded_with_rise(&self, blade: Blade) -> (Blade, f32) {
        if self.is_flat() {
            return (blade, 0.0);
        }
        let root = blade.rest[0];
        let normal = self.normal(root.x, root.z, NORMAL_STEP_M);
        let c = self.rise_bound(root.x, root.z, normal, blade.reach());
        (blade.raised(0.0, normal, c), c)
    }

    /// The terrain as glsl/common/terrain.glsl reads it: the header, then
    /// the words after it (each hill's x, z, H, L; each ridge's x, z, H, L
    /// and the cosine and sine of its heading, two words unused; the
    /// height map's samples). The shader sums in `height`'s order, with
    /// the ridges' cosine and sine taken from here.
    pub fn gpu_words(&self) -> (TerrainHeader, Vec<f32>) {
        let map = self.map.as_deref();
        let header = TerrainHeader {
            map_size: map.map_or([0, 0], |m| [m.columns, m.rows]),
            hills: self.hills.len() as u32,
            ridges: self.ridges.len() as u32,
            map_extent: map.map_or([0.0; 2], |m| m.extent),
            map_center: map.map_or([0.0; 2], |m| m.center),
        };
        let mut words = Vec::new();
        for h in &self.hills {
            words.extend([h.center[0], h.center[1], h.height, h.half_width]);
        }
        for r in &self.ridges {
            let (s, c) = r.heading.to_radians().sin_cos();
            words.extend([
                r.center[0],
                r.center[1],
                r.height,
                r.half_width,
                c,
                s,
                0.0,
                0.0,
            ]);
        }
        if let Some(m) = map {
            words.extend(&m.heights);
        }
        (header, words)
    }

    /// The upward unit normal at (x, z), from central differences over
    /// `step` metres; straight up where the terrain is flat.
    pub fn normal(&self, x: f32, z: f32, step: f32) -> Vec3 {
        if self.is_flat() {
            return Vec3::Y;
        }
        let dx = (self.height(x + step, z) - self.height(x - step, z)) / (2.0 * step);
        let dz = (self.height(x, z + step) - self.height(x, z - step)) / (2.0 * step);
        Vec3::new(-dx, 1.0, -dz).normalize()
    }

    /// The least c for which the ground within `reach` of the point on it
    /// over (x, z) lies under the paraboloid n . d = c |d|^2 over its
    /// tangent plane there (d from that point, n the upward normal
    /// `normal`): the largest n . d / |d|^2 over the ground's points on
    /// rings from 2 cm out to `reach`; 0 where the ground curves only down.
    pub fn rise_bound(&self, x: f32, z: f32, normal: Vec3, reach: f32) -> f32 {
        if self.is_flat() {
            return 0.0;
        }
        let root = Vec3::new(x, self.height(x, z), z);
        let (rings, around) = (12, 24);
        let mut c = 0f32;
        for k in 0..rings {
            let r = 0.02 + (reach - 0.02).max(0.0) * k as f32 / (rings - 1) as f32;
            for a in 0..around {
                let (s, co) = (a as f32 * std::f32::consts::TAU / around as f32).sin_cos();
                let (px, pz) = (x + r * co, z + r * s);
                let d = Vec3::new(px, self.height(px, pz), pz) - root;
                c = c.max(normal.dot(d) / d.length_squared());
            }
        }
        c
    }

    /// The lowest and highest ground over the rectangle `lo`..`hi` (x, z):
    /// sampled on a lattice of at most `step` metres, with every feature's
    /// crest or trough inside it; (0, 0) where the terrain is flat.
    pub fn range_over(&self, lo: [f32; 2], hi: [f32; 2], step: f32) -> (f32, f32) {
        if self.is_flat() {
            return (0.0, 0.0);
        }
        let inside = |x: f32, z: f32| (lo[0]..=hi[0]).contains(&x) && (lo[1]..=hi[1]).contains(&z);
        let n = |a: usize| (((hi[a] - lo[a]) / step).ceil() as usize).clamp(1, 4096);
        let (nx, nz) = (n(0), n(1));
        let mut points: Vec<(f32, f32)> = (0..=nz)
            .flat_map(|j| {
                (0..=nx).map(move |i| {
                    (
                        lo[0] + (hi[0] - lo[0]) * i as f32 / nx as f32,
                        lo[1] + (hi[1] - lo[1]) * j as f32 / nz as f32,
                    )
                })
            })
            .collect();
        points.extend(
            self.hills
                .iter()
                .map(|h| (h.center[0], h.center[1]))
                .filter(|&(x, z)| inside(x, z)),
        );
        points
            .into_iter()
            .map(|(x, z)| self.height(x, z))
            .fold((f32::MAX, f32::MIN), |(a, b), h| (a.min(h), b.max(h)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The steepest |grad h| found by central differences of 1 cm on a
    /// lattice of `step` metres over the square of side 2 `half` about
    /// the origin.
    fn steepest_sampled(t: &Terrain, half: f32, step: f32) -> f32 {
        let n = (2.0 * half / step) as i32;
        let mut most = 0f32;
        for i in 0..=n {
            for j in 0..=n {
                let (x, z) = (-half + i as f32 * step, -half + j as f32 * step);
                let dx = (t.height(x + 0.01, z) - t.height(x - 0.01, z)) / 0.02;
                let dz = (t.height(x, z + 0.01) - t.height(x, z - 0.01)) / 0.02;
                most = most.max(dx.hypot(dz));
            }
        }
        most
    }

    /// `max_slope` bounds the slope found anywhere, and is the slope
    /// itself for one hill (the fit's shortcut in glsl/cover/tiles.comp
    /// relies on the bound; a loose one only costs the shortcut).
    #[test]
    fn the_slope_bound_holds_and_is_tight_for_one_hill() {
        let hill = Terrain {
            hills: vec![Hill {
                center: [1.0, -2.0],
                height: -2.0,
                half_width: 2.5,
            }],
            ..Terrain::default()
        };
        let sampled = steepest_sampled(&hill, 8.0, 0.05);
        assert!(
            hill.max_slope() >= sampled,
            "{} {sampled}",
            hill.max_slope()
        );
        assert!(
            hill.max_slope() < 1.01 * sampled,
            "{} {sampled}",
            hill.max_slope()
        );
        let mixed = Terrain {
            map: Some(Arc::new(HeightMap {
                columns: 3,
                rows: 4,
                heights: vec![0.0, 0.5, 1.5, 0.2, 1.0, 0.0, 2.0, 0.3, 0.7, 0.0, 1.2, 0.4],
                extent: [8.0, 9.0],
                center: [1.0, 0.0],
            })),
            ridges: vec![Ridge {
                center: [0.0, 1.0],
                height: 1.5,
                half_width: 1.5,
                heading: 30.0,
            }],
            ..hill
        };
        let sampled = steepest_sampled(&mixed, 6.0, 0.05);
        assert!(
            mixed.max_slope() >= sampled,
            "{} {sampled}",
            mixed.max_slope()
        );
        assert_eq!(Terrain::default().max_slope(), 0.0);
    }

    #[test]
    fn features_follow_their_profiles() {
        let t = Terrain {
            hills: vec![Hill {
                center: [2.0, -1.0],
                height: 3.0,
                half_width: 4.0,
            }],
            ..Terrain::default()
        };
        assert_eq!(t.height(2.0, -1.0), 3.0);
        assert!((t.height(6.0, -1.0) - 1.5).abs() < 1e-6);
        assert!((t.height(2.0, 7.0) - 0.6).abs() < 1e-6);
        let r = Terrain {
            ridges: vec![Ridge {
                center: [0.0, 0.0],
                height: 2.0,
                half_width: 1.0,
                heading: 90.0,
            }],
            ..Terrain::default()
        };
        // Along +z: the crest; 1 m across (along x): half.
        assert!((r.height(0.0, 50.0) - 2.0).abs() < 1e-5);
        assert!((r.height(1.0, -30.0) - 1.0).abs() < 1e-5);
        assert!(r.normal(0.0, 3.0, 0.01).abs_diff_eq(Vec3::Y, 1e-3));
        assert!(r.normal(1.0, 3.0, 0.01).x > 0.5);
        assert_eq!(Terrain::default().height(3.0, 4.0), 0.0);
    }

    #[test]
    fn a_height_map_is_bilinear_and_held_at_its_edges() {
        let m = HeightMap {
            columns: 2,
            rows: 2,
            heights: vec![0.0, 1.0, 2.0, 3.0],
            extent: [4.0, 2.0],
            center: [0.0, 0.0],
        };
        assert_eq!(m.height(-2.0, -1.0), 0.0);
        assert_eq!(m.height(2.0, 1.0), 3.0);
        assert_eq!(m.height(0.0, 0.0), 1.5);
        assert_eq!(m.height(100.0, -100.0), 1.0);
        let t = Terrain {
            map: Some(Arc::new(m)),
            ..Terrain::default()
        };
        assert_eq!(t.range_over([-2.0, -1.0], [2.0, 1.0], 0.5), (0.0, 3.0));
    }
}
