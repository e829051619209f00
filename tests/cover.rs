//! The cover (`[grass.cover]`): tiles of blades made on the GPU around the
//! camera (glsl/cover/tiles.comp) against the CPU reference
//! (src/scene/cover.rs), bit for bit, on the default device with
//! validation on.

mod common;

use ash::vk;
use common::{finish, strict_gpu_with};
use glam::Vec2;
use meadow::compute::CoverTilePass;
use meadow::gpu::{Access, Buffer, CommandPool, Gpu};
use meadow::model::BladeVertex;
use meadow::scene::cover::{self, CoverTiles};
use meadow::scene::{BladeShape, Cover};

fn cover() -> Cover {
    Cover {
        density: 2.0,
        view_distance: 8.0,
        seed: Some(11),
        simulate_radius: 4.0,
    }
}

/// Words the buffer holds before the cover's blades: what the tile kernel
/// must leave alone.
const SENTINEL: u32 = 0xDEAD_BEEF;

/// The tiles around each camera position, made on the GPU one after the
/// other into one blade buffer after `base` blades of something else, and
/// read back after each (the cover's part), with whether the rest kept
/// its sentinel.
fn made_on_the_gpu(
    gpu: &Gpu,
    cover: &Cover,
    shape: &BladeShape,
    base: u32,
    cameras: &[Vec2],
) -> Vec<(Vec<BladeVertex>, bool)> {
    let commands = CommandPool::new(gpu, "cover test commands").unwrap();
    let most = cover::most_blades(cover) as usize;
    let words = (base as usize + most) * 4 * 8;
    let buffer = Buffer::with_data(
        gpu,
        &commands,
        "cover test blades",
        bytemuck::cast_slice(&vec![SENTINEL; words]),
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
        Access::COMPUTE_WRITE,
    )
    .unwrap();
    let pass = CoverTilePass::new(gpu, cover, cover.seed.unwrap(), shape, &buffer, base).unwrap();
    let made = cameras
        .iter()
        .map(|&camera| {
            let tiles = CoverTiles::around(cover, camera);
            let rec = commands.begin().unwrap();
            pass.record(&rec, &buffer, &tiles).unwrap();
            rec.submit_and_wait("cover tiles").unwrap();
            let all: Vec<BladeVertex> = buffer
                .read_back(gpu, &commands, (base as usize + most) * 4)
                .unwrap();
            let (before, cover) = all.split_at(base as usize * 4);
            let kept = bits(before).iter().all(|&w| w == SENTINEL);
            (cover.to_vec(), kept)
        })
        .collect();
    drop((pass, buffer, commands));
    made
}

fn bits(v: &[BladeVertex]) -> &[u32] {
    bytemuck::cast_slice(v)
}

#[test]
fn the_gpu_makes_the_tiles_bit_for_bit_as_the_cpu_and_a_tile_that_comes_back_is_the_same() {
    let cover = cover();
    let shape = BladeShape {
        drooping: 0.4,
        ..BladeShape::default()
    };
    // 25 tiles of 32 blades after 300 blades of the patches'; one binding
    // holds 256 blades, so the kernel runs in five batches, the first
    // two partly.
    let gpu = strict_gpu_with(Some(256 * 128));
    let cameras = [
        Vec2::new(0.5, 0.5),
        Vec2::new(-1000.0, 2000.0),
        Vec2::new(0.5, 0.5),
        Vec2::new(5.0, -3.0),
    ];
    let made_after = made_on_the_gpu(&gpu, &cover, &shape, 300, &cameras);
    let made_alone = made_on_the_gpu(&gpu, &cover, &shape, 0, &cameras[..1]);
    finish(gpu);

    let seed = cover::seed32(cover.seed.unwrap());
    for (camera, (gpu_vertices, kept)) in cameras.iter().zip(&made_after) {
        assert!(kept, "the kernel wrote before the cover's blades");
        let tiles = CoverTiles::around(&cover, *camera);
        let cpu = cover::vertices(seed, &shape, &tiles);
        assert_eq!(cpu.len(), gpu_vertices.len());
        let differing = bits(&cpu)
            .iter()
            .zip(bits(gpu_vertices))
            .filter(|(a, b)| a != b)
            .count();
        let first = (0..cpu.len()).find(|&i| bits(&cpu[i..i + 1]) != bits(&gpu_vertices[i..i + 1]));
        assert_eq!(
            differing,
            0,
            "around {camera}: {differing} words differ; first at vertex {first:?}: CPU {:?}, GPU {:?}",
            first.map(|i| cpu[i]),
            first.map(|i| gpu_vertices[i])
        );
    }
    let made: Vec<&Vec<BladeVertex>> = made_after.iter().map(|(v, _)| v).collect();
    // Where the cover starts in the buffer changes none of its blades.
    assert_eq!(bits(&made_alone[0].0), bits(made[0]));
    // The first camera's tiles, made again after others: the same bits.
    assert_eq!(bits(made[0]), bits(made[2]));
    // Moved by one tile and a bit: the tiles both hold sit in other slots
    // and hold the same blades.
    let (a, b) = (
        CoverTiles::around(&cover, cameras[0]),
        CoverTiles::around(&cover, cameras[3]),
    );
    let per = 4 * a.per_tile as usize;
    let mut shared = 0;
    for slot_a in 0..a.tile_count() as u32 {
        if let Some(slot_b) = (0..b.tile_count() as u32).find(|&s| b.tile(s) == a.tile(slot_a)) {
            let (sa, sb) = (slot_a as usize * per, slot_b as usize * per);
            assert_eq!(bits(&made[0][sa..sa + per]), bits(&made[3][sb..sb + per]));
            shared += 1;
        }
    }
    // Tiles -2..=2 and -1..=3 across, -2..=2 and -3..=1 along: 4 x 4 shared.
    assert_eq!(shared, 16, "tiles shared between the two cameras");
}
