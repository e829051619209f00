//! What the cover's tests (tests/cover.rs, cover_pose.rs,
//! cover_dynamics.rs) share: small covers and terrains, a steady wind on
//! the CPU and the GPU, and the tile pass run once and read back.

use ash::vk;
use glam::Vec2;
use glam::{UVec3, Vec3};
use meadow::compute::cover_tiles::{CoverSetup, CoverWind};
use meadow::compute::CoverTilePass;
use meadow::gpu::{Access, Buffer, CommandPool, Gpu};
use meadow::model::terrain::Terrain;
use meadow::model::wind::{WindField, WindGrid, WindSettings};
use meadow::model::BladeVertex;
use meadow::scene::cover::{self, CoverTiles};
use meadow::scene::{BladeShape, Cover, Grass};

/// Flat ground: the cover's blades at height 0, as before terrain.
pub const FLAT: Terrain = Terrain {
    map: None,
    hills: Vec::new(),
    ridges: Vec::new(),
};

pub fn cover() -> Cover {
    Cover {
        density: Some(2.0),
        view_distance: 8.0,
        seed: Some(11),
        simulate_radius: Some(4.0),
        size: None,
        center: None,
    }
}

/// Words the buffer holds before the cover's blades: what the tile kernel
/// must leave alone.
pub const SENTINEL: u32 = 0xDEAD_BEEF;

/// The tiles around each camera position, made on the GPU one after the
/// other into one blade buffer after `base` blades of something else, and
/// read back after each (the cover's part), with whether the rest kept
/// its sentinel.
pub fn made_on_the_gpu(
    gpu: &Gpu,
    terrain: &Terrain,
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
    let grass = Grass {
        shape: shape.clone(),
        ..Grass::default()
    };
    let frame = unused_frame_uniforms(gpu);
    let pass = CoverTilePass::new(
        gpu,
        &commands,
        CoverSetup {
            cover,
            seed: cover.seed.unwrap(),
            grass: &grass,
            vertices: &buffer,
            base,
            wind: None,
            frame: &frame,
            pose_drawn_only: false,
            states: None,
            presses: None,
            terrain,
            far_poses: None,
        },
    )
    .unwrap();
    let made = cameras
        .iter()
        .map(|&camera| {
            let tiles = CoverTiles::around(cover, camera);
            let rec = commands.begin().unwrap();
            pass.record(&rec, &tiles).unwrap();
            rec.submit_and_wait("cover tiles").unwrap();
            let all: Vec<BladeVertex> = buffer
                .read_back(gpu, &commands, (base as usize + most) * 4)
                .unwrap();
            let (before, cover) = all.split_at(base as usize * 4);
            let kept = bits(before).iter().all(|&w| w == SENTINEL);
            (cover.to_vec(), kept)
        })
        .collect();
    drop((pass, buffer, frame, commands));
    made
}

/// The frame uniforms a tile pass binds, as a renderer holds them.
pub fn frame_uniforms(gpu: &Gpu, uniforms: &meadow::render::FrameUniforms) -> Buffer {
    let mut buffer = Buffer::new(
        gpu,
        "cover test frame uniforms",
        std::mem::size_of::<meadow::render::FrameUniforms>() as u64,
        vk::BufferUsageFlags::UNIFORM_BUFFER,
        meadow::gpu::MemoryLocation::CpuToGpu,
    )
    .unwrap();
    buffer.write(0, std::slice::from_ref(uniforms));
    buffer
}

/// Frame uniforms for a pass that poses every blade (or none): never read.
pub fn unused_frame_uniforms(gpu: &Gpu) -> Buffer {
    frame_uniforms(gpu, &bytemuck::Zeroable::zeroed())
}

pub fn bits(v: &[BladeVertex]) -> &[u32] {
    bytemuck::cast_slice(v)
}

/// A scene of a cover beside a small meadow, the camera flying 30 m
/// along x in 3 s.
pub fn covered_scene(with_meadow: bool) -> meadow::scene::Scene {
    let meadow_table = if with_meadow {
        "[[grass.meadow]]\ncenter = [0.0, -3.0]\nsize = [2.0, 2.0]\ncount = 300\n"
    } else {
        ""
    };
    let text = format!(
        r#"name = "covered"
seed = 5

[camera]
position = [0.0, 1.5, 4.0]
target = [0.0, 0.3, -4.0]
fov_y = 50.0

[[camera.path]]
time = 0.0
position = [0.0, 1.5, 4.0]
target = [0.0, 0.3, -4.0]

[[camera.path]]
time = 3.0
position = [30.0, 1.5, 4.0]
target = [30.0, 0.3, -4.0]

[light]
shadow_map = 512

{meadow_table}
[grass.cover]
density = 3.0
view_distance = 10.0
"#
    );
    meadow::scene::file::parse(&text, "covered.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// The control points in a frame's blade buffer, the patches' and the
/// cover's.
pub fn blades_of(gpu: &Gpu, recorder: &meadow::frame::FrameRecorder) -> Vec<BladeVertex> {
    recorder
        .blades()
        .buffer()
        .read_back(
            gpu,
            recorder.commands(),
            recorder.blades().count() as usize * 4,
        )
        .unwrap()
}

/// Hills, a ridge and a height map together, slopes up to about 20
/// degrees around the origin.
pub fn hilly() -> Terrain {
    use meadow::model::terrain::{HeightMap, Hill, Ridge};
    Terrain {
        map: Some(std::sync::Arc::new(HeightMap {
            columns: 3,
            rows: 4,
            heights: vec![0.0, 0.5, 1.5, 0.2, 1.0, 0.0, 2.0, 0.3, 0.7, 0.0, 1.2, 0.4],
            extent: [20.0, 24.0],
            center: [3.0, -2.0],
        })),
        hills: vec![
            Hill {
                center: [2.0, 1.0],
                height: 3.0,
                half_width: 6.0,
            },
            Hill {
                center: [-7.0, -4.0],
                height: -1.5,
                half_width: 3.0,
            },
            // Steep (flanks to 39 degrees): blades leaning into it are
            // fitted (`cover::fitted`).
            Hill {
                center: [-2.0, -1.0],
                height: 1.5,
                half_width: 1.2,
            },
        ],
        ridges: vec![Ridge {
            center: [0.0, 5.0],
            height: 2.0,
            half_width: 4.0,
            heading: 30.0,
        }],
    }
}

/// The wind velocity as the GPU holds it, uploaded once (and writable by
/// a transfer, for a test that changes the wind).
pub fn wind_buffer(gpu: &Gpu, commands: &CommandPool, velocity: &[f32]) -> Buffer {
    Buffer::with_data(
        gpu,
        commands,
        "steady wind",
        bytemuck::cast_slice(velocity),
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        Access::COMPUTE_READ,
    )
    .unwrap()
}

/// A steady wind on a square grid `side` metres across from `corner`,
/// varying from face to face: 1.5-4.5 m/s along x, 0.2-1 m/s along z. The
/// grid, the CPU field and the velocity as the GPU holds it.
pub fn steady_wind(corner: Vec3, side: f32) -> (WindGrid, WindField, Vec<f32>) {
    steady_wind_over(&FLAT, corner, side)
}

/// `steady_wind` over `terrain`: from the lowest ground under the square
/// to 2 m over the highest, in the world's heights as a cover's window
/// over terrain stands (on terrain, 8 layers more).
pub fn steady_wind_over(
    terrain: &Terrain,
    corner: Vec3,
    side: f32,
) -> (WindGrid, WindField, Vec<f32>) {
    let (lo, hi) = ([corner.x, corner.z], [corner.x + side, corner.z + side]);
    let (low, high) = terrain.range_over(lo, hi, 0.25);
    let layers = if terrain.is_flat() { 4 } else { 12 };
    let grid = WindGrid::new(
        UVec3::new(8, layers, 8),
        Vec3::new(corner.x, corner.y + low, corner.z),
        Vec3::new(side, high - low + 2.0, side),
    )
    .unwrap();
    let settings = WindSettings {
        terrain: terrain.clone(),
        ..WindSettings::default()
    };
    let mut field = WindField::new(grid, &settings);
    for (i, v) in field.vel[0].iter_mut().enumerate() {
        *v = 1.5 + (i % 11) as f32 * 0.3;
    }
    for (i, v) in field.vel[2].iter_mut().enumerate() {
        *v = 1.0 - (i % 5) as f32 * 0.2;
    }
    let recorded = field.vel.iter().flatten().copied().collect();
    (grid, field, recorded)
}

/// A blade buffer for `blades` cover blades that the tile pass writes and
/// a test reads back.
pub fn cover_vertices(gpu: &Gpu, name: &str, blades: usize) -> Buffer {
    Buffer::new(
        gpu,
        name,
        (blades * 4 * std::mem::size_of::<BladeVertex>()) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
        meadow::gpu::MemoryLocation::GpuOnly,
    )
    .unwrap()
}

/// `tiles` made and posed on the GPU in the recorded wind (its grid and
/// velocity): every blade, or with `seen` (the frame's uniforms) only
/// those the frame may draw.
pub fn posed_on_the_gpu(
    gpu: &Gpu,
    terrain: &Terrain,
    cover: &Cover,
    grass: &Grass,
    (grid, recorded): (WindGrid, &[f32]),
    tiles: &CoverTiles,
    seen: Option<&meadow::render::FrameUniforms>,
) -> (Vec<BladeVertex>, u32) {
    let blades = tiles.blade_count() as usize;
    let commands = CommandPool::new(gpu, "cover pose commands").unwrap();
    let velocity = wind_buffer(gpu, &commands, recorded);
    let vertices = cover_vertices(gpu, "posed cover", blades);
    let frame = match seen {
        Some(u) => frame_uniforms(gpu, u),
        None => unused_frame_uniforms(gpu),
    };
    let pass = CoverTilePass::new(
        gpu,
        &commands,
        CoverSetup {
            pose_drawn_only: seen.is_some(),
            ..posing(cover, grass, &vertices, (&velocity, grid), &frame, terrain)
        },
    )
    .unwrap();
    let rec = commands.begin().unwrap();
    pass.record(&rec, tiles).unwrap();
    rec.submit_and_wait("posing the cover").unwrap();
    let posed = vertices.read_back(gpu, &commands, blades * 4).unwrap();
    let count = pass.posed();
    drop((pass, vertices, velocity, frame, commands));
    (posed, count)
}

/// The tile pass's setup for `cover` posed in a wind (`velocity` on
/// `grid`) into `vertices` from blade 0: every blade posed, none from a
/// dynamics' state; a test changes what it needs.
pub fn posing<'a>(
    cover: &'a Cover,
    grass: &'a Grass,
    vertices: &'a Buffer,
    (velocity, grid): (&'a Buffer, WindGrid),
    frame: &'a Buffer,
    terrain: &'a Terrain,
) -> CoverSetup<'a> {
    CoverSetup {
        cover,
        seed: cover.seed.unwrap(),
        grass,
        vertices,
        base: 0,
        wind: Some(CoverWind { velocity, grid }),
        frame,
        pose_drawn_only: false,
        states: None,
        presses: None,
        terrain,
        far_poses: None,
    }
}
