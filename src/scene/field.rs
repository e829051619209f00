//! The grass field generator: seeded and deterministic. Bunches are tufts of
//! blades splaying out from a point; meadows fill a rectangle. Each blade is
//! upright, curved or drooping, with random height, width, facing and
//! curvature (docs/method.md section 2).

use glam::{Vec2, Vec3};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;

use crate::error::{try_with_capacity, Result};
use crate::model::{Blade, BladeKind, BladePhysics, GrassBlade};
use crate::scene::{BladeShape, Grass, GrassDynamics, GrassPatch};

/// Generates every blade of every patch. The same grass and seed always
/// give the same blades, on every machine.
pub fn generate(grass: &Grass, seed: u64) -> Result<Vec<Blade>> {
    let shape = &grass.shape;
    let patches = grass.patches();
    let mut blades = try_with_capacity(
        patches.iter().map(GrassPatch::count).sum(),
        "the grass field's blades",
    )?;
    for (index, patch) in patches.iter().enumerate() {
        // One stream per patch, so editing one patch leaves the others alone.
        let mut rng =
            Pcg64Mcg::seed_from_u64(seed ^ (index as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        match *patch {
            GrassPatch::Bunch {
                center,
                radius,
                count,
            } => {
                for _ in 0..count {
                    // Uniform over the disc; the blade leans away from the tuft's centre.
                    let r = radius * rng.random::<f32>().sqrt();
                    let a = rng.random::<f32>() * std::f32::consts::TAU;
                    let offset = Vec2::new(a.cos(), a.sin()) * r;
                    let outward = a + rng.random_range(-0.6..0.6);
                    blades.push(blade(&mut rng, shape, Vec2::from(center) + offset, outward));
                }
            }
            GrassPatch::Meadow {
                center,
                size,
                count,
            } => {
                for _ in 0..count {
                    let p = Vec2::from(center)
                        + Vec2::new(
                            rng.random_range(-0.5..0.5) * size[0],
                            rng.random_range(-0.5..0.5) * size[1],
                        );
                    let facing = rng.random::<f32>() * std::f32::consts::TAU;
                    blades.push(blade(&mut rng, shape, p, facing));
                }
            }
        }
    }
    Ok(blades)
}

/// Draws each blade's physical parameters from the scene's ranges. A stream
/// of its own, so the shapes do not change when the physics ranges do.
pub fn physics(dynamics: &GrassDynamics, seed: u64) -> impl Iterator<Item = BladePhysics> + '_ {
    let mut rng = Pcg64Mcg::seed_from_u64(seed ^ 0xD1B5_4A32_D192_ED03);
    std::iter::repeat_with(move || {
        let mut draw = |[lo, hi]: [f32; 2]| lo + (hi - lo) * rng.random::<f32>();
        BladePhysics {
            edge_mass: draw(dynamics.edge_mass),
            sigma: draw(dynamics.sigma),
            tip_stiffness: draw(dynamics.tip_stiffness),
            stiffness_ratio: draw(dynamics.stiffness_ratio),
            damping_ratio: draw(dynamics.damping_ratio),
        }
    })
}

/// The blades as the grass dynamics reads them: shape plus physics.
pub fn dynamic_blades(
    blades: &[Blade],
    dynamics: &GrassDynamics,
    seed: u64,
) -> Result<Vec<GrassBlade>> {
    dynamics.validate()?;
    let mut out = try_with_capacity(blades.len(), "the blades' dynamics")?;
    for (b, p) in blades.iter().zip(physics(dynamics, seed)) {
        out.push(GrassBlade::new(b, &p)?);
    }
    Ok(out)
}

fn blade(rng: &mut Pcg64Mcg, shape: &BladeShape, root: Vec2, facing_angle: f32) -> Blade {
    let total = shape.upright + shape.curved + shape.drooping;
    let pick = rng.random::<f32>() * total;
    let kind = if pick < shape.upright {
        BladeKind::Upright
    } else if pick < shape.upright + shape.curved {
        BladeKind::Curved
    } else {
        BladeKind::Drooping
    };
    let h = rng.random_range(shape.height[0]..=shape.height[1]);
    let width = rng.random_range(shape.width[0]..=shape.width[1]);
    let c: f32 = rng.random(); // curvature within the kind
    let profile = profile(kind, c).map(|[x, y]| [x * h, y * h]);
    let facing = Vec3::new(facing_angle.cos(), 0.0, facing_angle.sin());
    Blade::from_profile(
        Vec3::new(root.x, 0.0, root.y),
        facing,
        profile,
        0.5 * width,
        kind,
        rng.random(),
    )
}

/// A blade's profile as (along the facing direction, up) pairs for a unit
/// height, by kind and the curvature `c` in [0, 1) within the kind.
pub fn profile(kind: BladeKind, c: f32) -> [[f32; 2]; 4] {
    match kind {
        BladeKind::Upright => [
            [0.0, 0.0],
            [0.0, 0.34],
            [0.04 + 0.06 * c, 0.67],
            [0.08 + 0.14 * c, 0.99],
        ],
        BladeKind::Curved => [
            [0.0, 0.0],
            [0.02, 0.36],
            [0.12 + 0.12 * c, 0.68],
            [0.34 + 0.26 * c, 0.86 - 0.1 * c],
        ],
        // Rises, then the last edge falls: two slope groups (paper Fig. 7).
        BladeKind::Drooping => [
            [0.0, 0.0],
            [0.06, 0.5],
            [0.3 + 0.1 * c, 0.84],
            [0.62 + 0.15 * c, 0.5 - 0.15 * c],
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    #[test]
    fn same_seed_same_field_other_seed_other_field() {
        let scene = Scene::builtin("fig10-few-bunches").unwrap();
        let a = generate(&scene.grass, 7).unwrap();
        let b = generate(&scene.grass, 7).unwrap();
        let c = generate(&scene.grass, 8).unwrap();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn all_three_kinds_appear_with_varied_heights() {
        let scene = Scene::builtin("table1").unwrap();
        let blades = generate(&scene.grass, 1).unwrap();
        for kind in [BladeKind::Upright, BladeKind::Curved, BladeKind::Drooping] {
            assert!(blades.iter().any(|b| b.kind == kind), "{kind:?} missing");
        }
        let heights: Vec<f32> = blades
            .iter()
            .map(|b| b.rest[1..].iter().map(|p| p.y).fold(0.0, f32::max))
            .collect();
        let min = heights.iter().cloned().fold(f32::MAX, f32::min);
        let max = heights.iter().cloned().fold(0.0, f32::max);
        assert!(max > 1.3 * min, "heights barely vary: {min}..{max}");
        // Roots on the ground, drooping tips below their third control point.
        for b in &blades {
            assert_eq!(b.rest[0].y, 0.0);
            if b.kind == BladeKind::Drooping {
                assert!(b.rest[3].y < b.rest[2].y);
            }
        }
    }
}
