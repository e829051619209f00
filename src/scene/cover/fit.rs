//! The cover's blades fitted to the ground they stand on and held above
//! it (docs/method.md, "The cover on terrain"): `fitted` turns a rest
//! shape leaning into a slope away from it, `held_above_ground` keeps a
//! far pose out of the ground. glsl/cover/tiles.comp does the same
//! arithmetic each frame; the turn's cosine and sine are the facing's
//! polynomials (`super::facing`), so x and z stay bit for bit.

use glam::{Vec2, Vec3};

use super::facing;
use crate::model::blade::{
    bezier, COVER_FIT_SAMPLES, COVER_FIT_SHRINKS, COVER_FIT_TURNS, COVER_HOLD_HALVINGS, FIT_ROOM,
};
use crate::model::grass::{self, GrassBlade};
use crate::model::terrain::{Terrain, NORMAL_STEP_M};
use crate::model::Blade;

/// How far a blade's curve (`points`, P0 its root) keeps above the
/// ground at its worst: over its points at t = 1/8 .. 1
/// (`COVER_FIT_SAMPLES`), the height above the ground under the point
/// less `FIT_ROOM` times its distance from the root (m). Summed as
/// glsl/cover/tiles.comp's `ground_clearance` does.
pub fn ground_clearance(points: &[Vec3; 4], terrain: &Terrain) -> f32 {
    let mut worst = f32::MAX;
    for k in 1..=COVER_FIT_SAMPLES {
        let p = bezier(points, k as f32 / COVER_FIT_SAMPLES as f32);
        let above = p.y - terrain.height(p.x, p.z);
        worst = worst.min(above - FIT_ROOM * (p - points[0]).length());
    }
    worst
}

/// What the fit asks of a rest shape (m; at least 0 where it fits): its
/// curve clear of the ground (`ground_clearance`), and each control point
/// `FIT_ROOM` a metre above the tangent plane at the root, of
/// upward normal `n`, so that contact's region keeps it inside
/// (`Blade::raised`) and no blade rests against the ground it stands on,
/// held there, as one drooping into a hollow would.
pub fn fit_clearance(rest: &[Vec3; 4], n: Vec3, terrain: &Terrain) -> f32 {
    let mut worst = ground_clearance(rest, terrain);
    for p in &rest[1..] {
        let d = *p - rest[0];
        worst = worst.min(n.dot(d) - FIT_ROOM * d.length());
    }
    worst
}

/// (cos, sin) of k pi / COVER_FIT_TURNS by the facing's polynomials
/// (`facing`): exact in its arguments, so the tile kernel turns a blade
/// bit for bit as this does.
fn fit_turn(k: i32) -> Vec2 {
    let quarter = (COVER_FIT_TURNS / 2) as i32;
    let quadrant = (k + quarter / 2).div_euclid(quarter);
    let u = 0.5 + (k - quarter * quadrant) as f32 / quarter as f32;
    facing(u, quadrant as u32)
}

/// `blade` turned about the vertical through its root by the angle whose
/// (cos, sin) is `turn` (x' = c x + s z, z' = c z - s x), never fused.
fn turned(blade: &Blade, turn: Vec2) -> Blade {
    let (c, s) = (turn.x, turn.y);
    let root = blade.rest[0];
    let spin = |d: Vec3| Vec3::new(c * d.x + s * d.z, d.y, c * d.z - s * d.x);
    Blade {
        rest: blade.rest.map(|p| {
            let d = spin(p - root);
            Vec3::new(root.x + d.x, p.y, root.z + d.z)
        }),
        width_dir: spin(blade.width_dir),
        ..*blade
    }
}

/// `blade`'s lean shrunk toward upright to `t` of itself.
fn shrunk(blade: &Blade, t: f32) -> Blade {
    let root = blade.rest[0];
    Blade {
        rest: blade.rest.map(|p| {
            Vec3::new(
                root.x + (p.x - root.x) * t,
                p.y,
                root.z + (p.z - root.z) * t,
            )
        }),
        ..*blade
    }
}

/// The cover's fit of a lifted blade's rest shape to the ground (the
/// patches' is `Blade::fitted`, which needs the ground's rise around
/// every root, more than the tile kernel can afford for every blade
/// every frame): where a point of its curve is under the ground, or
/// nearer it than `FIT_ROOM` allows (a blade leaning or drooping
/// into a slope, which would stand in the hill), or a control point is
/// not above the tangent plane at its root (`fit_clearance`), it is
/// turned about the vertical through its root as little as clears it, by
/// multiples of pi / COVER_FIT_TURNS, each way in turn; where no turn clears it (a
/// hollow tighter than the blade), turned where it keeps highest and its
/// lean shrunk toward upright as far as needed, upright at worst. Its
/// heights and edge lengths as they were but for the shrink; its width
/// stays horizontal. A blade that clears is returned as it is, and
/// glsl/cover/tiles.comp does the same arithmetic.
pub fn fitted(blade: Blade, terrain: &Terrain) -> Blade {
    let root = blade.rest[0];
    let n = terrain.normal(root.x, root.z, NORMAL_STEP_M);
    // The candidates in one sequence, as the tile kernel tries them:
    // the blade as made, the turns, then the best turn's shrinks.
    let turns = COVER_FIT_TURNS as i32;
    let turn = |k: i32| match k {
        0 => blade,
        _ => turned(&blade, fit_turn(k)),
    };
    let (mut best, mut highest) = (0, f32::MIN);
    for c in 0..=2 * turns + COVER_FIT_SHRINKS as i32 - 1 {
        let candidate = if c <= 2 * turns {
            turn(fit_turn_of(c))
        } else {
            let j = (c - 2 * turns) as f32;
            shrunk(&turn(best), 1.0 - j / COVER_FIT_SHRINKS as f32)
        };
        let clearance = fit_clearance(&candidate.rest, n, terrain);
        if clearance >= 0.0 {
            return candidate;
        }
        if c <= 2 * turns && clearance > highest {
            (best, highest) = (fit_turn_of(c), clearance);
        }
    }
    shrunk(&turn(best), 0.0)
}

/// The turn (in multiples of pi / COVER_FIT_TURNS) of the fit's `c`th
/// candidate: 0, then 1, -1, 2, -2 ..
fn fit_turn_of(c: i32) -> i32 {
    let k = (c + 1) / 2;
    if c % 2 == 1 {
        k
    } else {
        -k
    }
}

/// A far blade's angles held above the ground (the far field has no
/// contact; the simulated square's dynamics do): where the pose at
/// `angles` would put a point of its curve under the ground, or nearer it
/// than `FIT_ROOM` allows (the wind's balance pressing a blade down
/// a slope), the angles scaled toward rest, which the fit keeps clear, as
/// far as needed to `COVER_HOLD_HALVINGS` halvings; with whether they were.
/// On flat ground, or where the pose clears, `angles` as they are.
/// glsl/cover/tiles.comp does the same.
pub fn held_above_ground(terrain: &Terrain, b: &GrassBlade, angles: [f32; 4]) -> ([f32; 4], bool) {
    if terrain.is_flat() {
        return (angles, false);
    }
    let clears = |s: f32| {
        let points = grass::pose(b, angles.map(|a| a * s)).points;
        ground_clearance(&points, terrain) >= 0.0
    };
    if clears(1.0) {
        return (angles, false);
    }
    let (mut lo, mut hi) = (0.0f32, 1.0f32);
    for _ in 0..COVER_HOLD_HALVINGS {
        let mid = 0.5 * (lo + hi);
        if clears(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (angles.map(|a| a * lo), true)
}

#[cfg(test)]
mod tests {
    use super::super::tests::cover;
    use super::super::{blade, blade_on, grass_blade, physics, posed_vertices, CoverTiles};
    use super::*;
    use crate::model::quasi_static::{quasi_static_angles_within, FAR_ITERATIONS};
    use crate::model::BladeKind;
    use crate::scene::{BladeShape, GrassDynamics};

    /// The deepest any point of the blade's curve (sampled at 64 points)
    /// is under the ground (m; negative: above it).
    fn depth(rest: &[Vec3; 4], terrain: &Terrain) -> f32 {
        (0..=64)
            .map(|k| {
                let p = bezier(rest, k as f32 / 64.0);
                terrain.height(p.x, p.z) - p.y
            })
            .fold(f32::MIN, f32::max)
    }

    /// A round hill 2 m high and 2.5 m in half-width (flanks up to 27
    /// degrees) and a hollow 1 m deep, under
    /// 24,000 cover blades: fitted
    /// (`fitted`), no point of any blade's curve is under the ground, and
    /// a turned blade keeps its heights, its edges' lengths and a
    /// horizontal unit width. Rooted only (the fit undone), drooping
    /// blades hang into the rising ground.
    /// A round hill 2 m high and 2.5 m in half-width (flanks up to 27
    /// degrees) and a hollow 1 m deep.
    fn steep_hill() -> Terrain {
        Terrain {
            hills: vec![
                crate::model::terrain::Hill {
                    center: [0.0, 0.0],
                    height: 2.0,
                    half_width: 2.5,
                },
                crate::model::terrain::Hill {
                    center: [6.0, -5.0],
                    height: -1.0,
                    half_width: 1.0,
                },
            ],
            ..Terrain::default()
        }
    }

    #[test]
    fn on_a_steep_hill_no_cover_blade_stands_in_the_ground() {
        let terrain = steep_hill();
        let shape = BladeShape::default();
        let tiles = CoverTiles::around(&cover(60.0, 8.0), Vec2::ZERO);
        let (mut deepest, mut unfitted_deepest) = (f32::MIN, f32::MIN);
        let (mut under_unfitted, mut turned_blades, mut shrunk_blades) = (0, 0, 0);
        for (tile, index) in tiles.blades() {
            let made = terrain.lifted(blade(7, &shape, tile, index));
            let rooted = terrain.grounded(made);
            let fitted = blade_on(&terrain, 7, &shape, tile, index);
            let d = depth(&rooted.rest, &terrain);
            unfitted_deepest = unfitted_deepest.max(d);
            under_unfitted += (d > 0.0) as u32;
            deepest = deepest.max(depth(&fitted.rest, &terrain));
            if fitted.rest != rooted.rest {
                let lengths = |b: &Blade| b.edge_lengths();
                let shrank = lengths(&fitted)
                    .iter()
                    .zip(lengths(&rooted))
                    .any(|(a, b)| (a - b).abs() > 1e-5 * b);
                turned_blades += !shrank as u32;
                shrunk_blades += shrank as u32;
                for (a, b) in fitted.rest.iter().zip(&rooted.rest) {
                    assert_eq!(a.y, b.y);
                }
                assert_eq!(fitted.rest[0], rooted.rest[0]);
                assert!(fitted.width_dir.y == 0.0);
                assert!((fitted.width_dir.length() - 1.0).abs() < 1e-5);
            }
        }
        eprintln!(
            "{} cover blades: rooted only, {under_unfitted} with a point under the ground, \
             {:.1} mm at most; fitted ({turned_blades} turned, {shrunk_blades} shrunk), \
             the deepest point {:.2} mm",
            tiles.blade_count(),
            1e3 * unfitted_deepest,
            1e3 * deepest
        );
        assert!(
            under_unfitted > 5 && unfitted_deepest > 0.01,
            "the hill is too gentle to test the fit: {under_unfitted}, {unfitted_deepest}"
        );
        assert!(turned_blades > 5, "{turned_blades}");
        assert!(
            deepest <= 0.0,
            "a fitted blade is {:.2} mm in the ground",
            1e3 * deepest
        );

        // At the bottom of a pit tighter than itself no turn clears a
        // drooping blade: its lean shrinks toward upright.
        let (tile, index) = tiles
            .blades()
            .find(|&(t, i)| blade(7, &shape, t, i).kind == BladeKind::Drooping)
            .unwrap();
        let made = blade(7, &shape, tile, index);
        let root = made.rest[0];
        let pit = Terrain {
            hills: vec![crate::model::terrain::Hill {
                center: [root.x, root.z],
                height: -3.0,
                half_width: 0.15,
            }],
            ..Terrain::default()
        };
        let rooted = pit.grounded(pit.lifted(made));
        let fitted = blade_on(&pit, 7, &shape, tile, index);
        let lean = |b: &Blade| Vec2::new(b.rest[3].x - root.x, b.rest[3].z - root.z).length();
        eprintln!(
            "in a pit: rooted only {:.0} mm in the ground, its tip {:.0} mm out; fitted \
             {:.2} mm, {:.0} mm out",
            1e3 * depth(&rooted.rest, &pit),
            1e3 * lean(&rooted),
            1e3 * depth(&fitted.rest, &pit),
            1e3 * lean(&fitted)
        );
        assert!(depth(&rooted.rest, &pit) > 0.1);
        assert!(depth(&fitted.rest, &pit) <= 0.0);
        assert!(lean(&fitted) < 0.5 * lean(&rooted));
    }

    /// In a 7 m/s wind from four headings over the steep hill, the far
    /// field's quasi-static poses (`posed_vertices`) keep every point of
    /// every blade's curve above the ground, and the blades the ground
    /// holds still bend: none is held at rest. Posed at the wind's balance
    /// alone (no hold), blades bent down the slopes go into it.
    #[test]
    fn in_a_wind_the_ground_holds_the_far_blades_out_of_it() {
        let terrain = steep_hill();
        let shape = BladeShape::default();
        let dynamics = GrassDynamics::default();
        let tiles = CoverTiles::around(&cover(30.0, 8.0), Vec2::ZERO);
        let (mut deepest, mut unheld_deepest, mut unheld_under) = (f32::MIN, f32::MIN, 0);
        let (mut held, mut held_at_rest) = (0, 0);
        for heading in 0..4 {
            let a = heading as f32 * std::f32::consts::FRAC_PI_2 + 0.3;
            let wind = Vec3::new(7.0 * a.cos(), 0.0, 7.0 * a.sin());
            let posed = posed_vertices(&terrain, 7, &shape, &dynamics, &tiles, |_| wind).unwrap();
            for ((tile, index), v) in tiles.blades().zip(posed.chunks(4)) {
                let p: [Vec3; 4] = std::array::from_fn(|i| Vec3::from_slice(&v[i].position[..3]));
                deepest = deepest.max(depth(&p, &terrain));
                let b = grass_blade(&terrain, 7, &shape, &dynamics, tile, index).unwrap();
                let (balance, _) = quasi_static_angles_within(&b, wind, FAR_ITERATIONS);
                let d = depth(&grass::pose(&b, balance).points, &terrain);
                unheld_deepest = unheld_deepest.max(d);
                unheld_under += (d > 0.01) as u32;
                let (angles, was_held) = held_above_ground(&terrain, &b, balance);
                held += was_held as u32;
                held_at_rest += (was_held && angles == [0.0; 4]) as u32;
            }
        }
        eprintln!(
            "{} blades, 4 headings: at the balance alone {unheld_under} poses more than 1 cm \
             under the ground, {:.0} mm at most; held ({held}, {held_at_rest} of them at rest), \
             the deepest point {:.2} mm",
            tiles.blade_count(),
            1e3 * unheld_deepest,
            1e3 * deepest
        );
        assert!(
            unheld_under > 5 && unheld_deepest > 0.03,
            "{unheld_under} {unheld_deepest}"
        );
        assert!(
            deepest <= 0.0,
            "a far blade is {:.2} mm in the ground",
            1e3 * deepest
        );
        assert!(
            held >= unheld_under && held_at_rest == 0,
            "{held} {held_at_rest}"
        );
    }

    /// The simulated square's blades over the steep hill in a 7 m/s wind
    /// from two headings, 4 s of the paper's dynamics from rest on the CPU
    /// reference (ground contact on): no point of any blade's curve under
    /// the ground, and every blade moving (its tip at least 1 mm from
    /// rest). Rooted only (the fit undone), blades drooping into the
    /// hollow rest on contact's boundary and never move.
    #[test]
    fn near_the_camera_no_cover_blade_is_in_the_ground_or_still() {
        let terrain = steep_hill();
        let shape = BladeShape::default();
        let dynamics = GrassDynamics::default();
        let tiles = CoverTiles::around(&cover(20.0, 8.0), Vec2::ZERO);
        let mut fitted = Vec::new();
        let mut rooted_only = Vec::new();
        for (tile, index) in tiles.blades() {
            let b = grass_blade(&terrain, 7, &shape, &dynamics, tile, index).unwrap();
            let made = terrain.lifted(blade(7, &shape, tile, index));
            let rooted = terrain.grounded(made);
            if blade_on(&terrain, 7, &shape, tile, index).rest != rooted.rest {
                let physics = physics(7, &dynamics, tile, index);
                rooted_only.push(GrassBlade::new(&rooted, &physics).unwrap());
            }
            fitted.push(b);
        }
        let dt = 1.0 / 60.0;
        let substeps = grass::substeps(&fitted, dt).unwrap();
        // The deepest any blade went under the ground (m) and how many never
        // moved, over 4 s in each wind.
        let run = |blades: &[GrassBlade]| {
            let (mut deepest, mut still) = (f32::MIN, 0);
            for heading in [0.3f32, 0.3 + std::f32::consts::PI] {
                let wind = Vec3::new(7.0 * heading.cos(), 0.0, 7.0 * heading.sin());
                for b in blades {
                    let mut state = grass::GrassState::default();
                    let tip = grass::pose(b, [0.0; 4]).points[3];
                    let mut moved = 0f32;
                    for step in 0..240 {
                        grass::step(b, &mut state, wind, dt, substeps);
                        if step % 4 == 3 {
                            let p = grass::pose(b, state.angle).points;
                            moved = moved.max(p[3].distance(tip));
                            deepest = deepest.max(depth(&p, &terrain));
                        }
                    }
                    still += (moved < 1e-3) as u32;
                }
            }
            (deepest, still)
        };
        let (deepest, still) = run(&fitted);
        let (_, still_unfitted) = run(&rooted_only);
        eprintln!(
            "{} kept blades, 2 winds, 4 s: deepest point {:.2} mm under the ground, {still} \
             still; the {} the fit changed, rooted only: {still_unfitted} still",
            fitted.len(),
            1e3 * deepest,
            rooted_only.len()
        );
        assert!(
            deepest <= 0.01,
            "a blade went {:.1} mm into the ground",
            1e3 * deepest
        );
        assert_eq!(still, 0);
        assert!(still_unfitted > 0, "nothing to fit: the test shows nothing");
    }
}
