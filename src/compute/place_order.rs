//! The order the grass kernels step the blades in: by place (a Morton
//! order of the roots over the field), within each batch. The shipped
//! fields' blades lie in random order; stepped in that order, every SIMD
//! group and workgroup holds blades from all over the field, so a few
//! blades near a collider make every group take the contact's path (and
//! scatter the touching list). In place order neighbours share a group.
//! The blades keep their scene order everywhere else: the kernels write
//! each blade's control points at its own index (docs/architecture.md).

use std::ops::Range;

use crate::model::grass::GrassBlade;

/// The blade each slot steps, slot by slot: a permutation of each batch
/// of `batches` (which cover the blades in order), sorted by the Morton
/// code of the roots' x and z over the field's extent (ties in index
/// order).
pub fn by_place(blades: &[GrassBlade], batches: &[Range<u32>]) -> Vec<u32> {
    let (mut low, mut high) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    for b in blades {
        for (k, axis) in [0, 2].into_iter().enumerate() {
            low[k] = low[k].min(b.rest_root[axis]);
            high[k] = high[k].max(b.rest_root[axis]);
        }
    }
    let code = |b: &GrassBlade| {
        let cell = |k: usize, value: f32| {
            let span = (high[k] - low[k]).max(1e-6);
            (((value - low[k]) / span).clamp(0.0, 1.0) * 65535.0) as u32
        };
        morton(cell(0, b.rest_root[0]), cell(1, b.rest_root[2]))
    };
    let mut order = Vec::with_capacity(blades.len());
    for batch in batches {
        let start = order.len();
        order.extend(batch.clone());
        order[start..].sort_by_key(|&i| (code(&blades[i as usize]), i));
    }
    order
}

/// The bits of `x` and `z` (16 each) interleaved, x in the even bits.
fn morton(x: u32, z: u32) -> u32 {
    let spread = |v: u32| {
        let mut v = v & 0xffff;
        v = (v | (v << 8)) & 0x00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333;
        (v | (v << 1)) & 0x5555_5555
    };
    spread(x) | (spread(z) << 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blade_at(x: f32, z: f32) -> GrassBlade {
        GrassBlade {
            rest_root: [x, 0.0, z],
            ..GrassBlade::default()
        }
    }

    #[test]
    fn morton_interleaves_x_in_the_even_bits() {
        assert_eq!(morton(0b11, 0), 0b0101);
        assert_eq!(morton(0, 0b11), 0b1010);
        assert_eq!(morton(0xffff, 0xffff), u32::MAX);
    }

    #[test]
    fn each_batch_is_permuted_within_itself_and_neighbours_follow_each_other() {
        // A 16 x 16 lattice in a scrambled order, in two batches.
        let mut blades: Vec<GrassBlade> = (0..256)
            .map(|i| blade_at((i % 16) as f32, (i / 16) as f32))
            .collect();
        for i in 0..256 {
            blades.swap(i, (i * 97 + 13) % 256);
        }
        let batches = [0..128, 128..256];
        let order = by_place(&blades, &batches);
        for batch in &batches {
            let mut slots: Vec<u32> = order[batch.start as usize..batch.end as usize].to_vec();
            slots.sort();
            assert_eq!(slots, batch.clone().collect::<Vec<_>>());
        }
        // Consecutive slots are close: the mean step between them in
        // place order is short, where the scrambled order's is long.
        let root = |i: u32| {
            let r = blades[i as usize].rest_root;
            glam::Vec2::new(r[0], r[2])
        };
        let mean_step = |indices: &[u32]| {
            indices
                .windows(2)
                .map(|w| root(w[0]).distance(root(w[1])))
                .sum::<f32>()
                / (indices.len() - 1) as f32
        };
        let scrambled: Vec<u32> = (0..128).collect();
        let placed = mean_step(&order[..128]);
        assert!(
            placed < 0.5 * mean_step(&scrambled),
            "place order steps {placed} m on average"
        );
    }
}
