//! Grass everywhere (`[grass.cover]`): square tiles of `TILE_M` metres
//! around the camera, each holding the same number of blades, each blade
//! drawn from the cover's seed, its tile's coordinates and its index in
//! the tile alone. Nothing is kept: a tile that comes back holds the same
//! blades, and the GPU makes them (glsl/cover/tiles.comp) bit for bit as
//! this reference does.
//!
//! Bit for bit because both sides use only what IEEE 754 rounds the same
//! everywhere: integer hashing, conversion of 24-bit integers, and single
//! additions and multiplications, none fused (the shader's `precise`).
//! The facing's sine and cosine are polynomials on an eighth of a turn
//! with the quadrant picked by two bits, not the platform's sin and cos.
//! On terrain each blade is fitted to the ground and a far pose held
//! above it (fit.rs).

use glam::{Vec2, Vec3};

use super::{BladeShape, Cover, GrassDynamics};
use crate::error::Result;
use crate::model::grass::{self, GrassBlade};
use crate::model::quasi_static::{quasi_static_angles_within, FAR_ITERATIONS};
use crate::model::terrain::Terrain;
use crate::model::{Blade, BladeKind, BladePhysics, BladeVertex};

mod fit;
pub use fit::{fit_clearance, fitted, ground_clearance, held_above_ground};

/// A tile's side (m).
pub const TILE_M: f32 = 4.0;

/// The tiles made around one camera position: `side` x `side` of them
/// from tile `origin` (tile coordinates: the tile at (i, j) covers
/// x in [i, i + 1) TILE_M and z in [j, j + 1) TILE_M), `per_tile` blades
/// each, in the blade buffer tile after tile, row by row; of those, the
/// blades rooted within the cover's `bounds` grow (`Cover::bounds`), the
/// rest are left out: made without width, which no pass draws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoverTiles {
    pub origin: [i32; 2],
    pub side: u32,
    pub per_tile: u32,
    pub bounds: [f32; 4],
}

impl CoverTiles {
    /// The tiles whose squares reach within the view distance of `camera`
    /// (x, z), squared off: the camera's tile and `ceil(view_distance /
    /// TILE_M)` more on every side.
    pub fn around(cover: &Cover, camera: Vec2) -> Self {
        let reach = tiles_reached(cover.view_distance);
        let tile = (camera / TILE_M).floor();
        Self {
            origin: [tile.x as i32 - reach as i32, tile.y as i32 - reach as i32],
            side: 2 * reach + 1,
            per_tile: per_tile(cover.density()),
            bounds: cover.bounds(),
        }
    }

    /// Whether a blade rooted at `root` (x, z) grows: inside the bounds,
    /// their least edges included and their greatest not.
    pub fn grows_at(&self, root: Vec2) -> bool {
        let [x0, z0, x1, z1] = self.bounds;
        root.x >= x0 && root.x < x1 && root.y >= z0 && root.y < z1
    }

    /// The lowest and highest corner (x, z) of the tiles' squares.
    pub fn extent(&self) -> (Vec2, Vec2) {
        let low = Vec2::new(self.origin[0] as f32, self.origin[1] as f32) * TILE_M;
        (low, low + Vec2::splat(self.side as f32 * TILE_M))
    }

    pub fn tile_count(&self) -> u64 {
        self.side as u64 * self.side as u64
    }

    pub fn blade_count(&self) -> u64 {
        self.tile_count() * self.per_tile as u64
    }

    /// Every blade's tile and index in the tile, in the blade buffer's
    /// order: tile after tile, row by row (the tile kernel's order).
    pub fn blades(&self) -> impl Iterator<Item = ([i32; 2], u32)> + '_ {
        (0..self.tile_count() as u32)
            .flat_map(move |slot| (0..self.per_tile).map(move |index| (self.tile(slot), index)))
    }

    /// The tile coordinates of the blade buffer's `slot`th tile.
    pub fn tile(&self, slot: u32) -> [i32; 2] {
        [
            self.origin[0] + (slot % self.side) as i32,
            self.origin[1] + (slot / self.side) as i32,
        ]
    }
}

/// Tiles beyond the camera's own on each side for a view distance.
pub fn tiles_reached(view_distance: f32) -> u32 {
    (view_distance / TILE_M).ceil().max(0.0) as u32
}

/// Blades in a tile at `density` blades a square metre (at least one).
pub fn per_tile(density: f32) -> u32 {
    (density as f64 * (TILE_M * TILE_M) as f64).round().max(1.0) as u32
}

/// The blades `CoverTiles::around` makes at most for a cover, wherever the
/// camera is: what the blade buffer must hold.
pub fn most_blades(cover: &Cover) -> u64 {
    let side = 2 * tiles_reached(cover.view_distance) as u64 + 1;
    side * side * per_tile(cover.density()) as u64
}

/// The cover's seed as the kernel takes it: the 64-bit seed folded to 32.
pub fn seed32(seed: u64) -> u32 {
    (seed ^ (seed >> 32)) as u32
}

/// The blade shape's kind weights as the two cumulative thresholds a draw
/// in [0, total) is compared against, and the total.
pub fn kind_thresholds(shape: &BladeShape) -> [f32; 3] {
    let upright_or_curved = shape.upright + shape.curved;
    [
        shape.upright,
        upright_or_curved,
        upright_or_curved + shape.drooping,
    ]
}

/// The blades' hash (`model::hash::lowbias32`), the same in
/// glsl/cover/tiles.comp.
pub use crate::model::hash::lowbias32 as hash;

/// The key all of a blade's draws come from.
pub fn blade_key(seed: u32, tile: [i32; 2], index: u32) -> u32 {
    hash(seed ^ hash(tile[0] as u32 ^ hash(tile[1] as u32 ^ hash(index))))
}

/// The blade's `k`th draw: 24 bits.
pub fn draw_bits(key: u32, k: u32) -> u32 {
    hash(key ^ k.wrapping_mul(0x9e37_79b9)) >> 8
}

/// The blade's `k`th draw in [0, 1): exact, 24 bits over 2^24.
pub fn draw(key: u32, k: u32) -> f32 {
    draw_bits(key, k) as f32 * (1.0 / 16_777_216.0)
}

/// The draws, by number.
const DRAW_X: u32 = 0;
const DRAW_Z: u32 = 1;
const DRAW_FACING: u32 = 2;
const DRAW_QUADRANT: u32 = 3;
const DRAW_KIND: u32 = 4;
const DRAW_HEIGHT: u32 = 5;
const DRAW_WIDTH: u32 = 6;
const DRAW_CURVATURE: u32 = 7;
const DRAW_RAND: u32 = 8;

/// The facing polynomials' coefficients, by their bits: the shader holds
/// the same bits (`uintBitsToFloat`), so no compiler's reading of a
/// decimal literal can make the two sides differ.
const SIN_3: f32 = f32::from_bits(0xBE2A_AAAB); // -1/6
const SIN_5: f32 = f32::from_bits(0x3C08_8889); // 1/120
const SIN_7: f32 = f32::from_bits(0xB950_0D01); // -1/5040
const SIN_9: f32 = f32::from_bits(0x3638_EF1D); // 1/362880
const COS_2: f32 = -0.5;
const COS_4: f32 = f32::from_bits(0x3D2A_AAAB); // 1/24
const COS_6: f32 = f32::from_bits(0xBAB6_0B61); // -1/720
const COS_8: f32 = f32::from_bits(0x37D0_0D01); // 1/40320

/// (cos, sin) of an angle drawn uniformly over the circle: `u` in [0, 1)
/// across a quarter turn centred on the quadrant's axis, `quadrant` in
/// 0..4. Taylor polynomials to x^9 on [-pi/4, pi/4] (error below 3e-8):
/// additions and multiplications only.
pub fn facing(u: f32, quadrant: u32) -> Vec2 {
    let x = (u - 0.5) * std::f32::consts::FRAC_PI_2;
    let x2 = x * x;
    let s = x * (1.0 + x2 * (SIN_3 + x2 * (SIN_5 + x2 * (SIN_7 + x2 * SIN_9))));
    let c = 1.0 + x2 * (COS_2 + x2 * (COS_4 + x2 * (COS_6 + x2 * COS_8)));
    match quadrant & 3 {
        0 => Vec2::new(c, s),
        1 => Vec2::new(-s, c),
        2 => Vec2::new(-c, -s),
        _ => Vec2::new(s, -c),
    }
}

/// The `index`th blade of `tile`: the field generator's shapes
/// (`field::profile`), rooted uniformly in the tile, on flat ground
/// (`blade_on` roots it on the terrain).
pub fn blade(seed: u32, shape: &BladeShape, tile: [i32; 2], index: u32) -> Blade {
    let key = blade_key(seed, tile, index);
    let root = Vec2::new(
        (tile[0] as f32 + draw(key, DRAW_X)) * TILE_M,
        (tile[1] as f32 + draw(key, DRAW_Z)) * TILE_M,
    );
    let f = facing(draw(key, DRAW_FACING), draw_bits(key, DRAW_QUADRANT));
    let [upright, upright_or_curved, total] = kind_thresholds(shape);
    let pick = draw(key, DRAW_KIND) * total;
    let kind = if pick < upright {
        BladeKind::Upright
    } else if pick < upright_or_curved {
        BladeKind::Curved
    } else {
        BladeKind::Drooping
    };
    let between = |[lo, hi]: [f32; 2], u: f32| lo + (hi - lo) * u;
    let h = between(shape.height, draw(key, DRAW_HEIGHT));
    let width = between(shape.width, draw(key, DRAW_WIDTH));
    let profile =
        super::field::profile(kind, draw(key, DRAW_CURVATURE)).map(|[x, y]| [x * h, y * h]);
    let root = Vec3::new(root.x, 0.0, root.y);
    let facing = Vec3::new(f.x, 0.0, f.y);
    Blade {
        rest: profile.map(|[x, y]| root + facing * x + Vec3::Y * y),
        half_width: 0.5 * width,
        // UP x facing, unit to the polynomials' rounding: not normalised,
        // which would take a square root.
        width_dir: Vec3::new(f.y, 0.0, -f.x),
        kind,
        rand: draw(key, DRAW_RAND),
        ground: Vec3::Y,
        ground_curvature: 0.0,
    }
}

/// The `index`th blade of `tile` rooted on `terrain`: raised to the
/// ground's height at its root (`Terrain::lifted`, which the tile kernel
/// computes to its division's rounding), its rest shape fitted to the
/// ground (`fitted`), and swinging about the ground's normal at its root
/// with contact's paraboloid over the ground its rest shape keeps
/// (`Terrain::grounded`). On flat ground, `blade` itself.
pub fn blade_on(
    terrain: &Terrain,
    seed: u32,
    shape: &BladeShape,
    tile: [i32; 2],
    index: u32,
) -> Blade {
    if terrain.is_flat() {
        return blade(seed, shape, tile, index);
    }
    let lifted = terrain.lifted(blade(seed, shape, tile, index));
    terrain.grounded(fitted(lifted, terrain))
}

/// The physics draws: k_tip, k_root / k_tip and sigma (what the
/// quasi-static pose needs), then edge mass and damping ratio.
const DRAW_TIP_STIFFNESS: u32 = 9;
const DRAW_STIFFNESS_RATIO: u32 = 10;
const DRAW_SIGMA: u32 = 11;
const DRAW_EDGE_MASS: u32 = 12;
const DRAW_DAMPING_RATIO: u32 = 13;

/// The `index`th blade of `tile`'s physical parameters, from the scene's
/// ranges (`[grass.dynamics]`), drawn as the shape is.
pub fn physics(seed: u32, dynamics: &GrassDynamics, tile: [i32; 2], index: u32) -> BladePhysics {
    let key = blade_key(seed, tile, index);
    let between = |[lo, hi]: [f32; 2], k: u32| lo + (hi - lo) * draw(key, k);
    BladePhysics {
        edge_mass: between(dynamics.edge_mass, DRAW_EDGE_MASS),
        sigma: between(dynamics.sigma, DRAW_SIGMA),
        tip_stiffness: between(dynamics.tip_stiffness, DRAW_TIP_STIFFNESS),
        stiffness_ratio: between(dynamics.stiffness_ratio, DRAW_STIFFNESS_RATIO),
        damping_ratio: between(dynamics.damping_ratio, DRAW_DAMPING_RATIO),
    }
}

/// Where a blade is rooted (x, z): what `CoverTiles::grows_at` tests.
pub fn root_xz(blade: &Blade) -> Vec2 {
    Vec2::new(blade.rest[0].x, blade.rest[0].z)
}

/// A blade beyond the cover's bounds as the tile kernel leaves it: its
/// rest points without width (no pass draws it; the cull pass counts it
/// in neither list).
pub fn left_out(blade: &Blade) -> [BladeVertex; 4] {
    blade.vertices().map(|v| BladeVertex {
        half_width: [0.0; 3],
        ..v
    })
}

/// The control points of every blade of `tiles` in its quasi-static pose
/// (src/model/quasi_static.rs) for the wind `wind_at` gives at its rest
/// tip, held above the ground (`held_above_ground`), in the blade
/// buffer's order: what the tile kernel writes with a wind to pose them in
/// (to the solve's tolerance, not bit for bit).
pub fn posed_vertices(
    terrain: &Terrain,
    seed: u32,
    shape: &BladeShape,
    dynamics: &GrassDynamics,
    tiles: &CoverTiles,
    wind_at: impl Fn(Vec3) -> Vec3,
) -> Result<Vec<BladeVertex>> {
    let mut out = Vec::with_capacity(tiles.blade_count() as usize * 4);
    for (tile, index) in tiles.blades() {
        let made = terrain.lifted(blade(seed, shape, tile, index));
        if !tiles.grows_at(root_xz(&made)) {
            out.extend(left_out(&made));
            continue;
        }
        let rest = blade_on(terrain, seed, shape, tile, index);
        let b = GrassBlade::new(&rest, &physics(seed, dynamics, tile, index))?;
        let (balance, _) = quasi_static_angles_within(&b, wind_at(rest.rest[3]), FAR_ITERATIONS);
        let (angles, _) = held_above_ground(terrain, &b, balance);
        out.extend(grass::vertices(&b, &grass::pose(&b, angles)));
    }
    Ok(out)
}

/// The control points of every blade of `tiles` on `terrain`, in the
/// blade buffer's order: what the tile kernel writes (bit for bit on flat
/// ground; on terrain the heights to the division's rounding).
pub fn vertices(
    terrain: &Terrain,
    seed: u32,
    shape: &BladeShape,
    tiles: &CoverTiles,
) -> Vec<BladeVertex> {
    tiles
        .blades()
        .flat_map(|(tile, index)| {
            // Left out as made, not fitted (the tile kernel fits only
            // what grows).
            let made = terrain.lifted(blade(seed, shape, tile, index));
            if tiles.grows_at(root_xz(&made)) {
                blade_on(terrain, seed, shape, tile, index).vertices()
            } else {
                left_out(&made)
            }
        })
        .collect()
}

/// The band (m) inside `simulate_radius` over which a kept blade's
/// pressing fades out: beyond the radius no collider presses the far
/// field, so a pressed blade leaving the simulated square shows no jump.
pub use crate::model::contact::PRESS_FADE_M;

/// How much of a kept blade's pressing shows at `distance` (m, along the
/// ground) from the camera: 1 within `radius` less the band, 0 from the
/// radius on, smooth between (smoothstep: no kink either).
pub fn pressed_fade(radius: f32, distance: f32) -> f32 {
    let band = PRESS_FADE_M.min(radius);
    if band <= 0.0 {
        return 0.0;
    }
    let t = ((radius - distance) / band).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The tiles whose blades carry the paper's dynamics around a camera at
/// `camera` (x, z): those whose squares reach within `simulate_radius`.
pub fn kept_tiles(cover: &Cover, camera: Vec2) -> CoverTiles {
    let simulated = Cover {
        view_distance: cover.simulate_radius(),
        ..cover.clone()
    };
    CoverTiles::around(&simulated, camera)
}

/// The state slot among `side` x `side` that `tile` is kept in: its
/// coordinates wrapped, so a tile keeps its slot (and its blades' state)
/// for as long as it stays in the simulated square, and the tile that
/// replaces one leaving takes the slot it leaves.
pub fn state_slot(tile: [i32; 2], side: u32) -> u32 {
    let s = side as i32;
    (tile[0].rem_euclid(s) + s * tile[1].rem_euclid(s)) as u32
}

/// Whose pose a far blade's slot holds (`FarPose::tile`): the tile's
/// coordinates, 15 bits each, over a bit that no slot left unposed has
/// (0). Two tiles sharing a slot differ by a multiple of the square's side
/// in x or z, so they share a tag only 2^15 tiles (131 km) apart: a camera
/// that jumps that far between frames finds its blades' last poses taken
/// for theirs, for one frame.
pub fn far_tag(tile: [i32; 2]) -> u32 {
    const BITS: u32 = 0x7fff;
    (1 << 30) | (tile[0] as u32 & BITS) | ((tile[1] as u32 & BITS) << 15)
}

/// The `index`th blade of `tile` as the dynamics step it (its physics
/// from the same key as its shape).
pub fn grass_blade(
    terrain: &Terrain,
    seed: u32,
    shape: &BladeShape,
    dynamics: &GrassDynamics,
    tile: [i32; 2],
    index: u32,
) -> Result<GrassBlade> {
    GrassBlade::new(
        &blade_on(terrain, seed, shape, tile, index),
        &physics(seed, dynamics, tile, index),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(super) fn cover(density: f32, view_distance: f32) -> Cover {
        Cover {
            density: Some(density),
            view_distance,
            seed: None,
            simulate_radius: None,
            size: None,
            center: None,
        }
    }

    /// The simulated square's tiles take every state slot once wherever
    /// the camera is, negative coordinates included; a tile that stays in
    /// the square as the camera moves keeps its slot.
    #[test]
    fn kept_tiles_wrap_onto_their_slots_one_to_one() {
        let c = Cover {
            simulate_radius: Some(9.0),
            ..cover(2.0, 20.0)
        };
        let mut before: Option<CoverTiles> = None;
        for camera in [
            Vec2::new(0.5, 0.5),
            Vec2::new(-13.0, 7.0),
            Vec2::new(-14.1, 3.0),
            Vec2::new(-400.0, -9.0),
        ] {
            let kept = kept_tiles(&c, camera);
            assert_eq!(kept.side, 7);
            let mut taken = [false; 49];
            for n in 0..49 {
                let slot = state_slot(kept.tile(n), kept.side) as usize;
                assert!(!taken[slot], "slot {slot} taken twice");
                taken[slot] = true;
            }
            if let Some(b) = before.filter(|b| b.origin[0].abs_diff(kept.origin[0]) < 7) {
                for n in 0..49 {
                    let tile = b.tile(n);
                    let inside = (0..7).contains(&(tile[0] - kept.origin[0]))
                        && (0..7).contains(&(tile[1] - kept.origin[1]));
                    if inside {
                        assert_eq!(state_slot(tile, 7), state_slot(tile, kept.side));
                    }
                }
            }
            before = Some(kept);
        }
    }

    #[test]
    fn a_kept_blades_pressing_fades_out_smoothly_over_the_band() {
        let r = 30.0;
        assert_eq!(pressed_fade(r, 0.0), 1.0);
        assert_eq!(pressed_fade(r, r - PRESS_FADE_M), 1.0);
        assert_eq!(pressed_fade(r, r), 0.0);
        assert_eq!(pressed_fade(r, 100.0), 0.0);
        assert_eq!(pressed_fade(r, r - 0.5 * PRESS_FADE_M), 0.5);
        let mut last = 1.0;
        for n in 0..=400 {
            let w = pressed_fade(r, 25.0 + n as f32 * 0.0125);
            assert!(w <= last && last - w < 0.01, "{w} after {last}");
            last = w;
        }
        // A radius inside the band: the band shrinks to it.
        assert_eq!(pressed_fade(2.0, 0.0), 1.0);
        assert_eq!(pressed_fade(0.0, 0.0), 0.0);
    }

    #[test]
    fn the_coefficients_are_the_taylor_series() {
        assert_eq!(SIN_3, -1.0 / 6.0);
        assert_eq!(SIN_5, 1.0 / 120.0);
        assert_eq!(SIN_7, -1.0 / 5040.0);
        assert_eq!(SIN_9, 1.0 / 362_880.0);
        assert_eq!(COS_4, 1.0 / 24.0);
        assert_eq!(COS_6, -1.0 / 720.0);
        assert_eq!(COS_8, 1.0 / 40320.0);
    }

    #[test]
    fn the_facing_is_a_unit_vector_uniform_over_the_circle() {
        let mut per_octant = [0u32; 8];
        for i in 0..4000u32 {
            let f = facing(draw(hash(i), 0), draw_bits(hash(i), 1));
            assert!((f.length() - 1.0).abs() < 1e-6, "|{f}| = {}", f.length());
            let angle = f.y.atan2(f.x).rem_euclid(std::f32::consts::TAU);
            per_octant[(angle / std::f32::consts::FRAC_PI_4) as usize % 8] += 1;
        }
        // 500 expected in each; a binomial's spread is about 21.
        for n in per_octant {
            assert!((430..=570).contains(&n), "octants {per_octant:?}");
        }
        // Against the platform's sin and cos at the quarter turn's edges.
        for (u, q) in [(0.0, 0), (0.999_999, 1), (0.25, 2), (0.75, 3)] {
            let a =
                (u - 0.5) * std::f32::consts::FRAC_PI_2 + q as f32 * std::f32::consts::FRAC_PI_2;
            let f = facing(u, q);
            assert!(
                (f.x - a.cos()).abs() < 3e-7 && (f.y - a.sin()).abs() < 3e-7,
                "{u} {q}: {f}"
            );
        }
    }

    #[test]
    fn tiles_cover_the_view_distance_around_the_camera() {
        let c = cover(40.0, 30.0);
        let tiles = CoverTiles::around(&c, Vec2::new(-1.0, 9.0));
        assert_eq!(tiles.per_tile, 640);
        assert_eq!(tiles.side, 2 * 8 + 1);
        assert_eq!(tiles.origin, [-1 - 8, 2 - 8]);
        assert_eq!(tiles.blade_count(), most_blades(&c));
        // Every point within the view distance lies in one of the tiles.
        for k in 0..64 {
            let a = k as f32 * std::f32::consts::TAU / 64.0;
            let p = Vec2::new(-1.0, 9.0) + 30.0 * Vec2::new(a.cos(), a.sin());
            let t = (p / TILE_M).floor();
            let (i, j) = (t.x as i32 - tiles.origin[0], t.y as i32 - tiles.origin[1]);
            assert!((0..17).contains(&i) && (0..17).contains(&j), "{p} outside");
        }
        assert_eq!(per_tile(0.01), 1);
    }

    #[test]
    fn a_tile_holds_the_same_blades_from_any_camera_and_its_own_blades_only() {
        let shape = BladeShape::default();
        let flat = Terrain::default();
        let c = cover(2.0, 8.0);
        let a = CoverTiles::around(&c, Vec2::new(0.5, 0.5));
        let b = CoverTiles::around(&c, Vec2::new(9.0, -3.0));
        let (va, vb) = (
            vertices(&flat, 7, &shape, &a),
            vertices(&flat, 7, &shape, &b),
        );
        let per = 4 * a.per_tile as usize;
        let mut shared = 0;
        for slot_a in 0..a.tile_count() as u32 {
            let tile = a.tile(slot_a);
            let Some(slot_b) = (0..b.tile_count() as u32).find(|&s| b.tile(s) == tile) else {
                continue;
            };
            shared += 1;
            let (sa, sb) = (slot_a as usize * per, slot_b as usize * per);
            assert_eq!(va[sa..sa + per], vb[sb..sb + per], "tile {tile:?}");
            // Every root lies in its own tile.
            for v in va[sa..sa + per].chunks(4) {
                let root = Vec2::new(v[0].position[0], v[0].position[2]) / TILE_M;
                assert_eq!(root.floor(), Vec2::new(tile[0] as f32, tile[1] as f32));
            }
        }
        assert!(shared >= 9, "{shared} tiles shared");
        // Another seed, other blades.
        assert_ne!(vertices(&flat, 8, &shape, &a), va);
    }

    /// A bounded cover grows the unbounded one's blades rooted in its
    /// rectangle, bit for bit, and leaves the others out (no width); two
    /// rectangles side by side share no blade and leave none out between
    /// them.
    #[test]
    fn a_bounded_cover_grows_the_unbounded_ones_blades_within_its_rectangle() {
        let shape = BladeShape::default();
        let open = cover(3.0, 12.0);
        // x in [-7, 3) and [3, 13), z in [-14, 16).
        let left = Cover {
            size: Some([10.0, 30.0]),
            center: Some([-2.0, 1.0]),
            ..open.clone()
        };
        let right = Cover {
            center: Some([8.0, 1.0]),
            ..left.clone()
        };
        let camera = Vec2::new(1.3, 0.7);
        let flat = Terrain::default();
        let [o, l, r] = [&open, &left, &right].map(|c| CoverTiles::around(c, camera));
        assert_eq!((o.origin, o.side), (l.origin, l.side));
        let [vo, vl, vr] = [&o, &l, &r].map(|t| vertices(&flat, 5, &shape, t));
        let grows = crate::model::has_width;
        let (mut in_left, mut in_right, mut in_neither) = (0, 0, 0);
        for ((a, b), c) in vo.chunks(4).zip(vl.chunks(4)).zip(vr.chunks(4)) {
            let root = Vec2::new(a[0].position[0], a[0].position[2]);
            assert!(grows(a), "the unbounded cover grows every blade");
            let inside = (-7.0..13.0).contains(&root.x) && (-14.0..16.0).contains(&root.y);
            match (grows(b), grows(c)) {
                (true, true) => panic!("{root} grows in both rectangles"),
                (true, false) => {
                    in_left += 1;
                    assert_eq!(a, b);
                    assert!(root.x < 3.0);
                }
                (false, true) => {
                    in_right += 1;
                    assert_eq!(a, c);
                    assert!(root.x >= 3.0);
                }
                (false, false) => {
                    in_neither += 1;
                    assert!(!inside, "{root} grows in neither rectangle");
                    // Left out where it stood, without width.
                    let (at, out) = (&a[0].position, &b[0].position);
                    assert_eq!(at, out);
                }
            }
        }
        assert!(in_left > 100 && in_right > 100 && in_neither > 100);
    }

    #[test]
    fn the_cover_has_the_fields_kinds_heights_and_widths() {
        let shape = BladeShape::default();
        let blades: Vec<Blade> = (0..3000)
            .map(|i| blade(3, &shape, [i % 7, -(i / 7)], i as u32))
            .collect();
        let share = |kind| blades.iter().filter(|b| b.kind == kind).count() as f32 / 3000.0;
        for (kind, weight) in [
            (BladeKind::Upright, shape.upright),
            (BladeKind::Curved, shape.curved),
            (BladeKind::Drooping, shape.drooping),
        ] {
            assert!(
                (share(kind) - weight).abs() < 0.04,
                "{kind:?}: {}",
                share(kind)
            );
        }
        for b in &blades {
            let w = 2.0 * b.half_width;
            assert!(w >= shape.width[0] && w <= shape.width[1]);
            assert_eq!(b.rest[0].y, 0.0);
            assert!((b.width_dir.length() - 1.0).abs() < 1e-6);
        }
    }
}
