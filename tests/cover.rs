//! The cover (`[grass.cover]`): tiles of blades made on the GPU around the
//! camera (glsl/cover/tiles.comp) against the CPU reference
//! (src/scene/cover/), bit for bit, on the default device with
//! validation on.

mod common;

use ash::vk;
use common::{finish, strict_gpu_with};
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
const FLAT: Terrain = Terrain {
    map: None,
    hills: Vec::new(),
    ridges: Vec::new(),
};

fn cover() -> Cover {
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
const SENTINEL: u32 = 0xDEAD_BEEF;

/// The tiles around each camera position, made on the GPU one after the
/// other into one blade buffer after `base` blades of something else, and
/// read back after each (the cover's part), with whether the rest kept
/// its sentinel.
fn made_on_the_gpu(
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
    drop((pass, buffer, frame, commands));
    made
}

/// The frame uniforms a tile pass binds, as a renderer holds them.
fn frame_uniforms(gpu: &Gpu, uniforms: &meadow::render::FrameUniforms) -> Buffer {
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
fn unused_frame_uniforms(gpu: &Gpu) -> Buffer {
    frame_uniforms(gpu, &bytemuck::Zeroable::zeroed())
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
    let made_after = made_on_the_gpu(&gpu, &FLAT, &cover, &shape, 300, &cameras);
    let made_alone = made_on_the_gpu(&gpu, &FLAT, &cover, &shape, 0, &cameras[..1]);
    // Bounded: x in [-2, 4), z in [-5, 4); a camera at its edge and one
    // far outside it.
    let bounded = Cover {
        size: Some([6.0, 9.0]),
        center: Some([1.0, -0.5]),
        ..cover.clone()
    };
    let bounded_cameras = [cameras[0], cameras[3], cameras[1]];
    let made_bounded = made_on_the_gpu(&gpu, &FLAT, &bounded, &shape, 300, &bounded_cameras);
    finish(gpu);
    let seed = cover::seed32(cover.seed.unwrap());
    for (camera, (gpu_vertices, _)) in bounded_cameras.iter().zip(&made_bounded) {
        let tiles = CoverTiles::around(&bounded, *camera);
        let cpu = cover::vertices(&FLAT, seed, &shape, &tiles);
        assert_eq!(bits(&cpu), bits(gpu_vertices), "bounded, around {camera}");
        let growing = cpu
            .chunks(4)
            .filter(|v| meadow::model::has_width(v))
            .count();
        eprintln!(
            "bounded, around {camera}: {growing} of {} blades grow",
            cpu.len() / 4
        );
    }

    for (camera, (gpu_vertices, kept)) in cameras.iter().zip(&made_after) {
        assert!(kept, "the kernel wrote before the cover's blades");
        let tiles = CoverTiles::around(&cover, *camera);
        let cpu = cover::vertices(&FLAT, seed, &shape, &tiles);
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

/// A scene of a cover beside a small meadow, the camera flying 30 m
/// along x in 3 s.
fn covered_scene(with_meadow: bool) -> meadow::scene::Scene {
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
fn blades_of(gpu: &Gpu, recorder: &meadow::frame::FrameRecorder) -> Vec<BladeVertex> {
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

/// The frame makes the cover around the camera where it stands at each
/// frame's time, bit for bit as the CPU reference, after the meadow's
/// blades, which stay as they were uploaded; and it draws them.
#[test]
fn each_frame_makes_the_cover_around_the_camera_after_the_patches_blades() {
    use meadow::frame::FrameRecorder;
    use meadow::render::{FrameUniforms, ViewMode};
    for with_meadow in [true, false] {
        let scene = covered_scene(with_meadow);
        let cover = scene.grass.cover.clone().unwrap();
        let blades = scene.field().unwrap();
        assert_eq!(blades.len(), if with_meadow { 300 } else { 0 });
        let gpu = strict_gpu_with(None);
        let (w, h) = (160, 90);
        let mut recorder = FrameRecorder::new(&gpu, &scene, (w, h), 1, &blades, None).unwrap();
        let mut made = Vec::new();
        for time in [0.0, 1.5, 3.0] {
            let uniforms = FrameUniforms::new(&scene, w, h, ViewMode::Shaded, time);
            let frame = recorder.render(&gpu, &uniforms, 0).unwrap();
            let all = blades_of(&gpu, &recorder);
            let drawn = frame.cull.map(|c| c.in_view).unwrap_or(0);
            made.push((time, all, drawn, recorder.cover_blades()));
        }
        drop(recorder);
        finish(gpu);

        let patches: Vec<BladeVertex> = blades.iter().flat_map(|b| b.vertices()).collect();
        let seed = cover::seed32(scene.seed);
        let mut origins = Vec::new();
        for (time, all, drawn, generated) in &made {
            let (eye, _) = scene.camera.at(*time);
            let tiles = CoverTiles::around(&cover, Vec2::new(eye.x, eye.z));
            origins.push(tiles.origin);
            assert_eq!(*generated, tiles.blade_count());
            let (before, covered) = all.split_at(patches.len());
            assert_eq!(bits(before), bits(&patches), "the patches' blades changed");
            let cpu = cover::vertices(&FLAT, seed, &scene.grass.shape, &tiles);
            assert_eq!(
                bits(covered),
                bits(&cpu),
                "at {time} s the cover differs from the CPU's"
            );
            assert!(*drawn > 100, "at {time} s only {drawn} blades were drawn");
        }
        // The camera moved 15 m between frames, from x 0 to 15 to 30: the
        // tiles followed it, from the camera's tile 0 to 3 to 7.
        assert_eq!(origins[1][0] - origins[0][0], 3);
        assert_eq!(origins[2][0] - origins[1][0], 4);
    }
}

/// A cover over a ridge 200 m along the camera's flight, shadows off.
/// `path`: the camera flies there from the origin over 20 s; else it
/// stands where the flight ends.
fn covered_ridge(path: bool) -> meadow::scene::Scene {
    let (end, end_target) = ("[200.0, 7.6, 4.0]", "[200.0, 6.3, -4.0]");
    let camera = if path {
        format!(
            "[camera]\nposition = [0.0, 1.6, 4.0]\ntarget = [0.0, 0.3, -4.0]\nfov_y = 50.0\n\n\
             [[camera.path]]\ntime = 0.0\nposition = [0.0, 1.6, 4.0]\ntarget = [0.0, 0.3, -4.0]\n\n\
             [[camera.path]]\ntime = 20.0\nposition = {end}\ntarget = {end_target}\n"
        )
    } else {
        format!("[camera]\nposition = {end}\ntarget = {end_target}\nfov_y = 50.0\n")
    };
    let text = format!(
        r#"name = "covered-ridge"
seed = 5

{camera}
[light]
shadow_map = 0

[ground]
half_extent = 10.0

[[ground.ridge]]
center = [200.0, 0.0]
height = 6.0
half_width = 20.0
heading = 90.0

[grass.cover]
density = 3.0
view_distance = 10.0
"#
    );
    meadow::scene::file::parse(&text, "covered-ridge.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// Over terrain the cover's ground follows the camera: its blades stand
/// on the ridge 200 m along the flight, and the terrain's mesh, remade
/// about the camera as it flies (`terrain::mesh_centre`), draws the ground
/// under them. The frame there is the frame of a camera that started
/// there, pixel for pixel (with the mesh left where the flight began, the
/// ridge's grass stands over the flat backdrop 6 m below and the frames
/// differ).
#[test]
fn over_terrain_the_ground_follows_the_camera_as_if_it_had_started_there() {
    use meadow::frame::FrameRecorder;
    use meadow::render::{FrameUniforms, ViewMode};
    let (flying, standing) = (covered_ridge(true), covered_ridge(false));
    assert!(flying.planted().unwrap().blades.is_empty());
    let (w, h) = (160, 90);
    let gpu = strict_gpu_with(None);
    let frame_at = |scene: &meadow::scene::Scene, times: &[f32]| {
        let mut recorder = FrameRecorder::new(&gpu, scene, (w, h), 1, &[], None).unwrap();
        let mut last = None;
        for &time in times {
            let uniforms = FrameUniforms::new(scene, w, h, ViewMode::Shaded, time);
            last = Some(recorder.render(&gpu, &uniforms, 0).unwrap());
        }
        let rest = blades_of(&gpu, &recorder);
        (last.unwrap(), rest)
    };
    let (flown, flown_blades) = frame_at(&flying, &[0.0, 10.0, 20.0]);
    let (stood, _) = frame_at(&standing, &[0.0]);
    finish(gpu);

    // The blades around the ridge's crest stand on it.
    let roots: Vec<f32> = flown_blades
        .chunks(4)
        .filter(|v| meadow::model::has_width(v))
        .map(|v| v[0].position[1])
        .collect();
    let highest = roots.iter().fold(f32::MIN, |a, &b| a.max(b));
    assert!(highest > 5.5, "the highest root stands at {highest} m");
    let differing = flown
        .rgba
        .chunks(4)
        .zip(stood.rgba.chunks(4))
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differing, 0,
        "{differing} pixels differ between the flown-to and the started-at frame"
    );
    assert!(
        flown.cull.map_or(0, |c| c.in_view) > 100,
        "too few blades in view"
    );
}

/// A cover bounded to a rectangle the camera flies out of: each frame
/// makes the blades of the unbounded cover rooted within it, bit for bit
/// as the CPU, counts those alone as generated, and the cull pass lists
/// none of those left out, though many stand in view.
#[test]
fn a_bounded_cover_grows_and_draws_only_within_its_rectangle() {
    use meadow::frame::FrameRecorder;
    use meadow::render::{FrameUniforms, ViewMode};
    let mut scene = covered_scene(false);
    // x in [0, 24), z in [-18, 12): the camera starts on its least x's
    // edge, looking along it, and leaves it at 24 m.
    let c = scene.grass.cover.as_mut().unwrap();
    c.size = Some([24.0, 30.0]);
    c.center = Some([12.0, -3.0]);
    let cover = c.clone();
    let gpu = strict_gpu_with(None);
    let (w, h) = (160, 90);
    let mut recorder = FrameRecorder::new(&gpu, &scene, (w, h), 1, &[], None).unwrap();
    let mut made = Vec::new();
    for time in [0.0, 1.5, 3.0] {
        let uniforms = FrameUniforms::new(&scene, w, h, ViewMode::Shaded, time);
        let frame = recorder.render(&gpu, &uniforms, 0).unwrap();
        let all = blades_of(&gpu, &recorder);
        let cull = recorder.cull().expect("the scene culls");
        let lists = [
            cull.read_color_list(&gpu, recorder.commands()).unwrap(),
            cull.read_shadow_list(&gpu, recorder.commands()).unwrap(),
        ];
        assert!(frame.cull.is_some());
        made.push((
            time,
            all,
            lists,
            recorder.cover_blades(),
            uniforms.view_proj,
        ));
    }
    drop(recorder);
    finish(gpu);

    let seed = cover::seed32(scene.seed);
    for (time, all, lists, generated, view_proj) in &made {
        let (eye, _) = scene.camera.at(*time);
        let tiles = CoverTiles::around(&cover, Vec2::new(eye.x, eye.z));
        let cpu = cover::vertices(&FLAT, seed, &scene.grass.shape, &tiles);
        assert_eq!(bits(all), bits(&cpu), "at {time} s");
        let grows: Vec<bool> = cpu.chunks(4).map(meadow::model::has_width).collect();
        let growing = grows.iter().filter(|&&g| g).count() as u64;
        assert_eq!(*generated, growing, "at {time} s: blades generated");
        // The blades left out whose roots the camera sees: what a cull
        // blind to the bounds would list.
        let m = glam::Mat4::from_cols_array(view_proj);
        let seen_out = cpu
            .chunks(4)
            .zip(&grows)
            .filter(|(v, &g)| {
                let p = m * Vec3::from_slice(&v[0].position[..3]).extend(1.0);
                !g && p.x.abs() <= p.w && p.y.abs() <= p.w && p.z >= 0.0 && p.z <= p.w
            })
            .count();
        let [color, shadow] = lists;
        let listed_out = color
            .iter()
            .chain(shadow)
            .filter(|&&b| !grows[b as usize])
            .count();
        eprintln!(
            "at {time} s: {growing} of {} blades grow, {} drawn; {seen_out} left out in view, {listed_out} of them listed",
            grows.len(),
            color.len()
        );
        assert_eq!(listed_out, 0, "at {time} s the cull listed blades left out");
        if *time == 0.0 {
            assert!(seen_out > 100, "too few blades left out in view to tell");
            assert!(color.len() > 100, "only {} blades drawn", color.len());
        }
    }
}

/// 3 x 3 tiles of 16 blades around the origin, every one posed
/// quasi-statically (no simulated square).
fn small_quasi_static_cover() -> Cover {
    Cover {
        density: Some(1.0),
        view_distance: 4.0,
        seed: Some(3),
        simulate_radius: Some(0.0),
        size: None,
        center: None,
    }
}

/// In a steady wind the tile kernel poses each blade where its torques
/// balance, as the CPU reference does (`cover::posed_vertices`, the
/// quasi-static solve of src/model/quasi_static.rs), to the two solves'
/// rounding: the GPU's in f32, the CPU's small system in f64.
#[test]
fn in_a_steady_wind_the_gpu_poses_the_cover_where_its_torques_balance_as_the_cpu() {
    let cover = small_quasi_static_cover();
    let grass = Grass::default();
    let (grid, field, recorded) = steady_wind(Vec3::new(-8.0, 0.0, -8.0), 16.0);
    // 3 x 3 tiles of 16 blades around the origin.
    let tiles = CoverTiles::around(&cover, Vec2::ZERO);

    let gpu = strict_gpu_with(None);
    let (posed, count) =
        posed_on_the_gpu(&gpu, &FLAT, &cover, &grass, (grid, &recorded), &tiles, None);
    finish(gpu);
    assert_eq!(count as usize, posed.len() / 4, "blades counted as posed");

    let seed = cover::seed32(3);
    let cpu = cover::posed_vertices(&FLAT, seed, &grass.shape, &grass.dynamics, &tiles, |x| {
        field.sample(x)
    })
    .unwrap();
    let rest = cover::vertices(&FLAT, seed, &grass.shape, &tiles);
    let (mut differs, mut moved) = (0.0f32, 0.0f32);
    for ((g, c), r) in posed.iter().zip(&cpu).zip(&rest) {
        let at = |v: &BladeVertex| Vec3::from_slice(&v.position[..3]);
        differs = differs.max(at(g).distance(at(c)));
        moved = moved.max(at(c).distance(at(r)));
        assert_eq!(g.position[3], c.position[3], "the colour draw");
    }
    eprintln!("posed cover: GPU and CPU within {differs:e} m; tips moved up to {moved} m");
    assert!(moved > 0.1, "the wind barely posed the blades: {moved} m");
    assert!(differs < 1e-4, "GPU and CPU poses differ by {differs} m");
}

/// Issue 65, item 7: a far blade goes from last frame's pose towards its
/// balance as its dynamics could, not at once. Three passes over one
/// pass's tiles: the steady wind, then that wind reversed (every balance
/// on the other side: the jump a stateless pose makes) for two frames of
/// 1/30 s. The GPU's poses follow the CPU reference (`far_tracked` from
/// each blade's last angles and rates, at `far_frequency`, towards the
/// balance continued from there: `quasi_static_angles_from`) to the solves'
/// rounding, the kernel's largest tip move is the CPU's, and it is a
/// fraction of the stateless jump (a pass with the tracking off, whose
/// poses are the balances themselves). Measured: 5.3e-7 m; the second
/// frame's largest move 0.057 m of a flip up to 0.80 m. With the far
/// blades shown at their balance at once by hand: 0.77 m off, fails.
#[test]
fn a_far_blade_goes_towards_a_new_balance_as_the_cpu_without_jumping() {
    use meadow::model::quasi_static::{
        far_frequency, far_tracked, quasi_static_angles_from, quasi_static_angles_within,
        FAR_ITERATIONS,
    };
    let cover = small_quasi_static_cover();
    let grass = Grass::default();
    let (grid, field, recorded) = steady_wind(Vec3::new(-8.0, 0.0, -8.0), 16.0);
    let reversed: Vec<f32> = recorded.iter().map(|v| -v).collect();
    let tiles = CoverTiles::around(&cover, Vec2::ZERO);
    let blades = tiles.blade_count() as usize;
    let dt = 1.0 / 30.0;

    let gpu = strict_gpu_with(None);
    let commands = CommandPool::new(&gpu, "cover tracking commands").unwrap();
    let velocity = wind_buffer(&gpu, &commands, &recorded);
    let vertices = cover_vertices(&gpu, "tracked cover", blades);
    let frame = unused_frame_uniforms(&gpu);
    let mut pass = CoverTilePass::new(
        &gpu,
        &commands,
        CoverSetup {
            cover: &cover,
            seed: 3,
            grass: &grass,
            vertices: &vertices,
            base: 0,
            wind: Some(CoverWind {
                velocity: &velocity,
                grid,
            }),
            frame: &frame,
            pose_drawn_only: false,
            states: None,
            presses: None,
            terrain: &FLAT,
            far_poses: None,
        },
    )
    .unwrap();
    let run = |pass: &mut CoverTilePass, wind: Option<&[f32]>, elapsed: f32| {
        pass.set_elapsed(elapsed);
        let rec = commands.begin().unwrap();
        if let Some(w) = wind {
            rec.uses(&[meadow::gpu::BufferUse::new(
                &velocity,
                Access::TRANSFER_WRITE,
            )]);
            rec.update_buffer(&velocity, 0, bytemuck::cast_slice(w));
        }
        pass.record(&rec, &vertices, &tiles).unwrap();
        rec.submit_and_wait("posing the cover").unwrap();
        vertices
            .read_back::<BladeVertex>(&gpu, &commands, blades * 4)
            .unwrap()
    };
    run(&mut pass, None, 0.0);
    run(&mut pass, Some(&reversed), dt);
    let tracked = run(&mut pass, None, dt);
    let (far_jump, jump) = pass.tip_jumps();
    pass.set_far_tracking(false);
    let stateless = run(&mut pass, None, dt);
    drop((pass, vertices, velocity, frame, commands));
    finish(gpu);

    // The CPU: each blade's balance in each wind, its pose tracked from
    // the first balance at rest through two frames of the reversed wind.
    let seed = cover::seed32(3);
    let at = |v: &BladeVertex| Vec3::from_slice(&v.position[..3]);
    let (mut differs, mut cpu_jump, mut flip) = (0.0f32, 0.0f32, 0.0f32);
    let mut field_reversed = field.clone();
    for axis in &mut field_reversed.vel {
        for v in axis.iter_mut() {
            *v = -*v;
        }
    }
    for (n, (tile, index)) in tiles.blades().enumerate() {
        let b =
            cover::grass_blade(&FLAT, seed, &grass.shape, &grass.dynamics, tile, index).unwrap();
        let tip = b.rest_point(3);
        let (first, _) = quasi_static_angles_within(&b, field.sample(tip), FAR_ITERATIONS);
        let reversed_at = field_reversed.sample(tip);
        let (after, _) = quasi_static_angles_within(&b, reversed_at, FAR_ITERATIONS);
        // Each frame's balance continued from the pose the frame before.
        let balance_from =
            |start| quasi_static_angles_from(&b, reversed_at, start, FAR_ITERATIONS).0;
        let omega = far_frequency(&b);
        let once = far_tracked((first, [0.0; 4]), balance_from(first), omega, dt);
        let twice = far_tracked(once, balance_from(once.0), omega, dt);
        let (was, now, balance, before) = (
            posed_at(&b, once.0),
            posed_at(&b, twice.0),
            posed_at(&b, after),
            posed_at(&b, first),
        );
        for (g, c) in tracked[4 * n..4 * n + 4].iter().zip(&now) {
            differs = differs.max(at(g).distance(at(c)));
        }
        cpu_jump = cpu_jump.max(at(&now[3]).distance(at(&was[3])));
        flip = flip.max(at(&balance[3]).distance(at(&before[3])));
        for (g, c) in stateless[4 * n..4 * n + 4].iter().zip(&balance) {
            differs = differs.max(at(g).distance(at(c)));
        }
    }
    eprintln!(
        "{blades} blades: GPU and CPU within {differs:e} m; the largest tip move in the second frame {jump} m (CPU {cpu_jump} m), the balances' flip up to {flip} m"
    );
    assert!(differs < 1e-4, "GPU and CPU poses differ by {differs} m");
    assert_eq!(far_jump, jump, "every blade is posed quasi-statically");
    assert!(
        (jump - cpu_jump).abs() < 1e-4,
        "the kernel's {jump} m, the CPU's {cpu_jump} m"
    );
    assert!(
        flip > 0.2,
        "the reversed wind barely moves the balances: {flip} m"
    );
    assert!(
        jump < 0.25 * flip,
        "a tip moved {jump} m in a frame of a {flip} m flip"
    );
}

/// `blade`'s control points at `angle` (the CPU's pose).
fn posed_at(blade: &meadow::model::GrassBlade, angle: [f32; 4]) -> [BladeVertex; 4] {
    use meadow::model::grass;
    grass::vertices(blade, &grass::pose(blade, angle))
}

/// Hills, a ridge and a height map together, slopes up to about 20
/// degrees around the origin.
fn hilly() -> Terrain {
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

/// On terrain the tile kernel roots each blade where the CPU does
/// (`Terrain::lifted`, `cover::fitted`): x and z bit for bit, the heights to the divisions'
/// rounding (a device's division may round otherwise than the CPU's;
/// lavapipe's does not), and poses it in the wind at its raised tip as
/// the CPU reference does, to the solves' rounding, in a wind window over
/// the hills.
#[test]
fn on_terrain_the_gpu_roots_and_poses_the_cover_where_the_cpu_does() {
    let terrain = hilly();
    let cover = Cover {
        density: Some(12.0),
        ..cover()
    };
    let shape = BladeShape::default();
    let cameras = [Vec2::new(0.5, 0.5), Vec2::new(-3.0, 7.0)];
    let pose_cover = Cover {
        density: Some(12.0),
        view_distance: 8.0,
        seed: Some(3),
        simulate_radius: Some(0.0),
        size: None,
        center: None,
    };
    let grass = Grass::default();
    // A wind window over the hills: each blade feels the wind where it
    // stands.
    let (grid, field, recorded) = steady_wind_over(&terrain, Vec3::new(-14.0, 0.0, -14.0), 28.0);
    let posed_tiles = CoverTiles::around(&pose_cover, Vec2::ZERO);

    let gpu = strict_gpu_with(None);
    let made = made_on_the_gpu(&gpu, &terrain, &cover, &shape, 0, &cameras);
    let (posed, _) = posed_on_the_gpu(
        &gpu,
        &terrain,
        &pose_cover,
        &grass,
        (grid, &recorded),
        &posed_tiles,
        None,
    );
    finish(gpu);

    let seed = cover::seed32(cover.seed.unwrap());
    let (mut same_height, mut highest, mut lowest, mut most) = (0usize, f32::MIN, f32::MAX, 0f32);
    for (camera, (gpu_vertices, _)) in cameras.iter().zip(&made) {
        let cpu = cover::vertices(&terrain, seed, &shape, &CoverTiles::around(&cover, *camera));
        assert_eq!(cpu.len(), gpu_vertices.len());
        for (c, g) in cpu.iter().zip(gpu_vertices) {
            for k in [0, 2, 3] {
                assert_eq!(
                    c.position[k].to_bits(),
                    g.position[k].to_bits(),
                    "around {camera}"
                );
            }
            assert_eq!(
                c.width.map(f32::to_bits),
                g.width.map(f32::to_bits),
                "around {camera}"
            );
            let (y, gy) = (c.position[1], g.position[1]);
            most = most.max((y - gy).abs() / y.abs().max(1.0));
            same_height += (y.to_bits() == gy.to_bits()) as usize;
            highest = highest.max(y);
            lowest = lowest.min(y);
        }
    }
    let points = 4 * made.iter().map(|(v, _)| v.len() / 4).sum::<usize>();
    // The blades the fit turned or shrank (`cover::fitted`), which the
    // GPU must have fitted alike to match above.
    let fitted = cameras
        .iter()
        .flat_map(|camera| {
            CoverTiles::around(&cover, *camera)
                .blades()
                .collect::<Vec<_>>()
        })
        .filter(|&(tile, index)| {
            let made = terrain.lifted(cover::blade(seed, &shape, tile, index));
            cover::blade_on(&terrain, seed, &shape, tile, index).rest != made.rest
        })
        .count();
    eprintln!(
        "on terrain: heights {lowest:.2} to {highest:.2} m, {same_height} of {points} bit for bit, \
         the rest within {most:e} of their size; {fitted} blades fitted to the ground"
    );
    assert!(
        fitted >= 10,
        "only {fitted} blades were fitted to the ground"
    );
    assert!(
        highest - lowest > 3.0,
        "the terrain barely raised the blades"
    );
    assert!(
        most <= 4.0 * f32::EPSILON,
        "heights differ by {most:e} of their size"
    );

    let cpu = cover::posed_vertices(
        &terrain,
        cover::seed32(3),
        &grass.shape,
        &grass.dynamics,
        &posed_tiles,
        |x| field.sample(x),
    )
    .unwrap();
    let rest = cover::vertices(&terrain, cover::seed32(3), &grass.shape, &posed_tiles);
    let (mut differs, mut moved) = (0.0f32, 0.0f32);
    for ((g, c), r) in posed.iter().zip(&cpu).zip(&rest) {
        let at = |v: &BladeVertex| Vec3::from_slice(&v.position[..3]);
        differs = differs.max(at(g).distance(at(c)));
        moved = moved.max(at(c).distance(at(r)));
    }
    // The blades the ground held (`cover::held_above_ground`), which the
    // GPU must have held alike to match.
    let held = posed_tiles
        .blades()
        .filter(|&(tile, index)| {
            let seed = cover::seed32(3);
            let b = cover::grass_blade(&terrain, seed, &grass.shape, &grass.dynamics, tile, index)
                .unwrap();
            let root = Vec2::new(b.rest[0][0], b.rest[0][2]);
            let (balance, _) = meadow::model::quasi_static::quasi_static_angles_within(
                &b,
                field.sample(b.rest_point(3)),
                meadow::model::quasi_static::FAR_ITERATIONS,
            );
            posed_tiles.grows_at(root) && cover::held_above_ground(&terrain, &b, balance).1
        })
        .count();
    eprintln!(
        "posed on terrain: GPU and CPU within {differs:e} m; tips moved up to {moved} m; \
         {held} held above the ground"
    );
    assert!(moved > 0.1, "the wind barely posed the blades: {moved} m");
    assert!(held >= 3, "only {held} blades were held above the ground");
    assert!(differs < 1e-4, "GPU and CPU poses differ by {differs} m");
}

/// What a cover cannot do yet is refused in one line naming it: `--blades`
/// on a scene whose only grass is a cover; gusts entering the moving
/// window's side, obstacles fixed in it. A cover on hills, with colliders
/// and wind sources, is taken.
#[test]
fn a_cover_refuses_what_it_cannot_do_yet_in_one_line() {
    let mut steppe = meadow::scene::Scene::builtin("steppe").unwrap();
    let err = steppe.set_blade_count(1000).unwrap_err().to_string();
    assert!(err.contains("only grass is a [grass.cover]"), "{err}");
    assert_eq!(err.lines().count(), 1);
    let mut hills = meadow::scene::Scene::builtin("hills").unwrap();
    // Its gusts would be refused first (below).
    if let Some(inflow) = hills.wind.inflow.as_mut() {
        inflow.gust = Default::default();
    }
    let mut text = meadow::scene::file::to_toml(&hills);
    text += "\n[grass.cover]\ndensity = 2.0\nview_distance = 20.0\n";
    let covered =
        meadow::scene::file::parse(&text, "hills-covered.toml").unwrap_or_else(|e| panic!("{e}"));
    assert!(!covered.ground.terrain().is_flat());
    assert!(covered.planted().is_ok(), "a cover on hills is refused");
    // Colliders and wind sources stand in the world; over terrain the
    // window takes them above the ground (`WindField::world_point`).
    for extra in [
        // Over the ridge's crest (the ground 2.4 m up there: a ball lower
        // would be in the hill, refused by `check::above_ground`).
        "\n[[collider]]\nkind = \"sphere\"\nradius = 0.2\nposition = [0.0, 3.0, 0.0]\n",
        "\n[[wind.source]]\nposition = [0.0, 0.5, 0.0]\ndirection = [1.0, 0.0, 0.0]\nstrength = 2.0\nradius = 1.0\n",
    ] {
        let scene = meadow::scene::file::parse(&(text.clone() + extra), "hills-covered.toml")
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(scene.planted().is_ok());
    }
    // The wind window follows the camera: no gusts entering at its side,
    // no obstacles fixed in its cells.
    let steppe = meadow::scene::Scene::builtin("steppe").unwrap();
    let mut gusty = steppe.clone();
    gusty.wind.inflow.as_mut().unwrap().gust.amplitude = 0.5;
    gusty.wind.inflow.as_mut().unwrap().gust.frequency = 0.3;
    let obstacle =
        "\n[[wind.obstacle]]\nkind = \"box\"\nmin = [1.0, 0.0, 1.0]\nmax = [2.0, 1.0, 2.0]\n";
    for (text, field) in [
        (meadow::scene::file::to_toml(&gusty), "wind.inflow.gust"),
        (
            meadow::scene::file::to_toml(&steppe) + obstacle,
            "wind.obstacle",
        ),
    ] {
        let err = meadow::scene::file::parse(&text, "steppe-plus.toml")
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(field) && err.contains("follows the camera"),
            "{err}"
        );
        assert_eq!(err.lines().count(), 1);
    }
}

/// The wind velocity as the GPU holds it, uploaded once (and writable by
/// a transfer, for a test that changes the wind).
fn wind_buffer(gpu: &Gpu, commands: &CommandPool, velocity: &[f32]) -> Buffer {
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
fn steady_wind(corner: Vec3, side: f32) -> (WindGrid, WindField, Vec<f32>) {
    steady_wind_over(&FLAT, corner, side)
}

/// `steady_wind` over `terrain`: from the lowest ground under the square
/// to 2 m over the highest, in the world's heights as a cover's window
/// over terrain stands (on terrain, 8 layers more).
fn steady_wind_over(terrain: &Terrain, corner: Vec3, side: f32) -> (WindGrid, WindField, Vec<f32>) {
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
fn cover_vertices(gpu: &Gpu, name: &str, blades: usize) -> Buffer {
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
fn posed_on_the_gpu(
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
            cover,
            seed: cover.seed.unwrap(),
            grass,
            vertices: &vertices,
            base: 0,
            wind: Some(CoverWind {
                velocity: &velocity,
                grid,
            }),
            frame: &frame,
            pose_drawn_only: seen.is_some(),
            states: None,
            presses: None,
            terrain,
            far_poses: None,
        },
    )
    .unwrap();
    let rec = commands.begin().unwrap();
    pass.record(&rec, &vertices, tiles).unwrap();
    rec.submit_and_wait("posing the cover").unwrap();
    let posed = vertices.read_back(gpu, &commands, blades * 4).unwrap();
    let count = pass.posed();
    drop((pass, vertices, velocity, frame, commands));
    (posed, count)
}

/// Posing only what the frame may draw changes nothing the frame draws:
/// every blade the kernel leaves at rest is, posed, in neither the colour
/// nor the shadow pass's list (the cull pass's CPU reference,
/// `CullView::test`), and every other blade is posed as with every blade
/// posed. Most of a cover lies outside a camera's view.
#[test]
fn posing_only_what_the_frame_may_draw_changes_nothing_drawn() {
    use meadow::render::visibility::CullView;
    use meadow::render::{FrameUniforms, ViewMode};
    let mut scene = covered_scene(false);
    // A low sun behind the camera: blades behind it cast into the view.
    scene.light.direction = [0.0, 0.2, 1.0];
    let cover = Cover {
        density: Some(2.0),
        view_distance: 20.0,
        seed: Some(9),
        simulate_radius: None,
        size: None,
        center: None,
    };
    let grass = scene.grass.clone();
    let (grid, _, recorded) = steady_wind(Vec3::new(-24.0, 0.0, -24.0), 48.0);
    let (eye, _) = scene.camera.at(0.0);
    let tiles = CoverTiles::around(&cover, Vec2::new(eye.x, eye.z));
    let uniforms = FrameUniforms::new(&scene, 320, 180, ViewMode::Shaded, 0.0);

    let gpu = strict_gpu_with(None);
    let (every, _) = posed_on_the_gpu(&gpu, &FLAT, &cover, &grass, (grid, &recorded), &tiles, None);
    let (drawn_only, counted) = posed_on_the_gpu(
        &gpu,
        &FLAT,
        &cover,
        &grass,
        (grid, &recorded),
        &tiles,
        Some(&uniforms),
    );
    finish(gpu);

    let view = CullView {
        view_proj: glam::Mat4::from_cols_array(&uniforms.view_proj),
        eye,
        light: Vec3::from_slice(&uniforms.light_dir[..3]),
        floor: 0.0,
        shadows: true,
        thinning: meadow::render::thinning::Thinning::of(&scene),
        edge_on: scene.cull.edge_on,
        filter_reach: meadow::render::visibility::filter_reach(
            &glam::Mat4::from_cols_array(&uniforms.light_view_proj),
            meadow::render::shadow::params_of(scene.light.shadow_map),
        ),
    };
    let rest = cover::vertices(&FLAT, cover::seed32(9), &grass.shape, &tiles);
    let (mut posed, mut left) = (0, 0);
    for ((a, b), r) in every
        .chunks(4)
        .zip(drawn_only.chunks(4))
        .zip(rest.chunks(4))
    {
        if bits(a) == bits(b) {
            posed += 1;
            continue;
        }
        assert_eq!(bits(b), bits(r), "a blade neither posed nor at rest");
        let (seen, margins) = view.test(a.try_into().unwrap());
        assert!(
            !seen.in_view && !seen.caster,
            "a blade left at rest would be drawn posed (margins {margins:?})"
        );
        left += 1;
    }
    eprintln!(
        "{posed} blades posed, {left} left at rest, of {}",
        posed + left
    );
    assert_eq!(counted, posed, "the kernel's count of the blades it posed");
    assert!(posed >= 50, "only {posed} blades posed");
    assert!(
        left >= posed,
        "only {left} of {} left at rest",
        posed + left
    );
}

/// A meadow under a cover's wind window, a 20 x 20 m window of 1 m cells
/// in a turbulent 4 m/s wind; the camera stands for a second, then flies
/// 8 m along x and 6 m along z in 3 s, the window following it.
fn window_scene() -> meadow::scene::Scene {
    let text = r#"name = "window"
seed = 8

[camera]
position = [-4.0, 1.5, -3.0]
target = [0.0, 0.3, 0.0]
fov_y = 50.0

[[camera.path]]
time = 0.0
position = [-4.0, 1.5, -3.0]
target = [0.0, 0.3, 0.0]

[[camera.path]]
time = 1.0
position = [-4.0, 1.5, -3.0]
target = [0.0, 0.3, 0.0]

[[camera.path]]
time = 4.0
position = [4.0, 1.5, 3.0]
target = [0.0, 0.3, 0.0]

[[grass.meadow]]
center = [0.0, 0.0]
size = [2.0, 2.0]
count = 60

[grass.cover]
density = 1.0
view_distance = 8.0

[wind]
cells = [20, 6, 20]
height = 3.0
window = [20.0, 20.0]
turbulence = { intensity = 0.3, length_scale = 3.0, seed = 2 }

[wind.inflow]
speed = 4.0
"#;
    meadow::scene::file::parse(text, "window.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// The meadow's tips after each step of 4 s of `window_scene`, the wind
/// window following the camera or held where it started; and before which
/// steps it moved.
fn traced_tips(scene: &meadow::scene::Scene, follow: bool) -> (Vec<Vec<Vec3>>, Vec<bool>) {
    let gpu = strict_gpu_with(None);
    let mut rig = common::sim::SimRig::new(&gpu, scene);
    let dt = scene.wind.dt;
    let mut tips = Vec::new();
    let mut moved = Vec::new();
    for n in 0..(4.0 / dt).round() as usize {
        let (eye, _) = scene.camera.at(n as f32 * dt);
        moved.push(follow && rig.follow(Vec2::new(eye.x, eye.z)));
        rig.run(1);
        let tip: Vec<Vec3> = rig
            .vertices(&gpu)
            .chunks(4)
            .map(|v| common::to_vec3(v[3].position))
            .collect();
        tips.push(tip);
    }
    drop(rig);
    finish(gpu);
    (tips, moved)
}

/// Issue 40, item 3: blades traced while the wind window moves under the
/// camera show no jump at a move. Each blade's kick at step n is the
/// third difference of its tip over steps n - 3 to n (the change of its
/// change of step: a force that jumps shows whole there, the blade's own
/// sway of a few hertz smoothed). A move's jump is how much it changes
/// the kicks: the tips' kicks at the step after a move against theirs at
/// that step with the window held where it started (the meadow lies
/// inside both windows, so both runs are the same physics but for the
/// window's far sides). Every move's jump must be under a tenth of the
/// ordinary kick. Measured: 2e-7 m against 3e-5 m. Fails when the grass
/// samples the wind at the window's old corner (1.1e-3 m) or the
/// turbulence stays on the grid (1.2e-3 m).
#[test]
fn a_traced_blade_shows_no_jump_when_the_wind_window_moves() {
    let scene = window_scene();
    let (followed, moved) = traced_tips(&scene, true);
    let (held, _) = traced_tips(&scene, false);
    // Each blade's kick at step n in a run, and the mean over the blades
    // of `f` of a run's kick and the held run's.
    let kick = |tips: &[Vec<Vec3>], n: usize, i: usize| {
        tips[n][i] - 3.0 * tips[n - 1][i] + 3.0 * tips[n - 2][i] - tips[n - 3][i]
    };
    let blades = followed[0].len();
    let mean = |f: &dyn Fn(usize) -> f32| (0..blades).map(f).sum::<f32>() / blades as f32;
    // From half a second on: the blades have left their rest shape.
    let settled = (0.5 / scene.wind.dt) as usize;
    let mut ordinary = Vec::new();
    let mut jumps = Vec::new();
    for n in settled..followed.len() {
        let jump = mean(&|i| (kick(&followed, n, i) - kick(&held, n, i)).length());
        if moved[n] {
            jumps.push((n, jump));
        } else if !moved[n - 1] && !moved[n - 2] {
            ordinary.push(mean(&|i| kick(&held, n, i).length()));
        }
    }
    ordinary.sort_by(f32::total_cmp);
    let typical = ordinary[ordinary.len() / 2];
    let worst = jumps.iter().map(|j| j.1).fold(0.0f32, f32::max);
    eprintln!(
        "{} moves change the tips' kick by at most {worst:.2e} m; the ordinary kick {typical:.2e} m (median of {} steps)",
        jumps.len(),
        ordinary.len()
    );
    assert!(jumps.len() >= 10, "{} moves", jumps.len());
    assert!(
        worst < 0.1 * typical,
        "a move changes the blades' kick by {worst:.2e} m, against an ordinary kick of {typical:.2e} m"
    );
}

/// Issue 40, item 2: near the camera the cover's blades carry the paper's
/// dynamics (`CoverDynamics`), as the CPU steps them (`GrassField`): the
/// tiles reaching within `simulate_radius` keep their blades' state in the
/// slot their coordinates wrap to; a tile coming in starts at its
/// quasi-static pose, still. Over 30 steps in one wind, the camera moved a
/// tile along x, then 40 in a wind half again as strong (the blades swing
/// to it): the GPU's states follow the CPU's, a kept tile's state carried
/// on, the new column's started where it came in (fails with the states
/// not kept across the move, or not started). Then the tile pass poses
/// every blade: within the radius less the band from its state, beyond
/// it quasi-statically, in the band the two blended
/// (`cover::dynamic_weight`), as the CPU does.
#[test]
fn near_the_camera_the_cover_runs_the_papers_dynamics_as_the_cpu() {
    kept_dynamics_against_the_cpu(&FLAT, &[]);
}

/// The same on hills, a ridge and a height map in a wind window over
/// them: the kept blades rooted on the ground (and held over it by ground
/// contact), each feeling the wind where it stands in the world.
#[test]
fn on_terrain_the_kept_blades_feel_the_wind_where_they_stand_as_the_cpu() {
    kept_dynamics_against_the_cpu(&hilly(), &[]);
}

/// A ball rolling over the hills and a walker crossing the kept tiles
/// press the cover's blades as the CPU's `GrassField` does (the grass step
/// in the cover's slots, its colliders binned over the square it keeps as
/// that moves, one walker crossing the tiles that came in; a tile coming
/// in starts unpressed), and the tile kernel
/// poses them pressed (`pressed_pose`, faded over the band as the angles
/// are). The pressed blades lie lower than the rest. Fails with the tile
/// kernel posing them unpressed (the poses), the kept blades stepped
/// without the colliders, or the bins left where the square first was
/// (the states).
#[test]
fn near_the_camera_a_rolling_ball_presses_the_cover_as_the_cpu() {
    use meadow::model::contact::{Collider, ColliderKind};
    let terrain = hilly();
    let on_ground = |x: f32, z: f32, above: f32| Vec3::new(x, terrain.height(x, z) + above, z);
    let ball = Collider {
        kind: ColliderKind::Sphere,
        radius: 0.8,
        path: vec![on_ground(-1.0, 0.5, 0.8), on_ground(7.0, 2.5, 0.8)],
        path_speed: 6.0,
        roll: true,
        ..Default::default()
    };
    let walker = Collider {
        kind: ColliderKind::Capsule,
        radius: 0.4,
        height: 1.8,
        path: vec![on_ground(3.0, -3.0, 0.0), on_ground(4.0, 4.0, 0.0)],
        path_speed: 3.0,
        ..Default::default()
    };
    // One crossing the tiles that come in at the move (x 12-16 m).
    let newcomer = Collider {
        path: vec![on_ground(15.0, -3.0, 0.0), on_ground(15.0, 4.0, 0.0)],
        ..walker.clone()
    };
    kept_dynamics_against_the_cpu(&terrain, &[ball, walker, newcomer]);
}

fn kept_dynamics_against_the_cpu(
    terrain: &Terrain,
    colliders: &[meadow::model::contact::Collider],
) {
    use meadow::compute::wind_pass::WindInput;
    use meadow::compute::CoverDynamics;
    use meadow::model::grass::{self, GrassState};
    use meadow::model::quasi_static::{quasi_static_angles_within, FAR_ITERATIONS};
    use meadow::model::GrassField;

    let cover = Cover {
        density: Some(1.0),
        view_distance: 12.0,
        seed: Some(21),
        simulate_radius: Some(7.0),
        size: None,
        center: None,
    };
    let grass = Grass::default();
    let seed = cover::seed32(21);
    let (grid, mut field, calm) = steady_wind_over(terrain, Vec3::new(-16.0, 0.0, -16.0), 40.0);
    let strong: Vec<f32> = calm.iter().map(|v| 1.5 * v).collect();
    let dt = 1.0 / 60.0;
    let eyes = [Vec2::new(1.0, 1.0), Vec2::new(5.5, 1.0)];

    let gpu = strict_gpu_with(None);
    let commands = CommandPool::new(&gpu, "cover dynamics commands").unwrap();
    let velocity = wind_buffer(&gpu, &commands, &calm);
    let input = WindInput {
        grid,
        velocity: &velocity,
        canopy: None,
        subgrid: None,
    };
    let setup = meadow::compute::cover_dynamics::CoverDynamicsSetup {
        cover: &cover,
        seed,
        grass: &grass,
        dt,
        camera: eyes[0],
        terrain,
        colliders,
    };
    let mut dynamics = CoverDynamics::new(&gpu, &commands, setup, &input).unwrap();
    let rec = commands.begin().unwrap();
    let mut step = 0u64;
    for (phase, eye) in eyes.iter().enumerate() {
        if phase == 1 {
            rec.uses(&[meadow::gpu::BufferUse::new(
                &velocity,
                Access::TRANSFER_WRITE,
            )]);
            rec.update_buffer(&velocity, 0, bytemuck::cast_slice(&strong));
        }
        dynamics.record_follow(&rec, *eye).unwrap();
        for _ in 0..[30, 40][phase] {
            dynamics.record_step(&rec, meadow::model::contact::step_end_time(step, dt));
            step += 1;
        }
    }
    rec.submit_and_wait("cover dynamics").unwrap();
    let states = dynamics.grass().read_states(&gpu, &commands).unwrap();
    let presses = dynamics.grass().read_presses(&gpu, &commands).unwrap();
    let gpu_substeps = dynamics.grass().substeps();
    let kept = *dynamics.square();
    let stepped = dynamics.blade_count() as usize;

    // The tile pass poses the cover around the last eye from those states.
    let tiles = CoverTiles::around(&cover, eyes[1]);
    let vertices = cover_vertices(&gpu, "posed cover", tiles.blade_count() as usize);
    let frame = unused_frame_uniforms(&gpu);
    let mut pass = CoverTilePass::new(
        &gpu,
        &commands,
        CoverSetup {
            cover: &cover,
            seed: 21,
            grass: &grass,
            vertices: &vertices,
            base: 0,
            wind: Some(CoverWind {
                velocity: &velocity,
                grid,
            }),
            frame: &frame,
            pose_drawn_only: false,
            states: Some(dynamics.states()),
            presses: dynamics.presses(),
            terrain,
            far_poses: dynamics.far_poses(),
        },
    )
    .unwrap();
    pass.set_dynamics(Some(&kept), eyes[1]);
    let rec = commands.begin().unwrap();
    pass.record(&rec, &vertices, &tiles).unwrap();
    rec.submit_and_wait("cover tiles").unwrap();
    let posed: Vec<BladeVertex> = vertices
        .read_back(&gpu, &commands, tiles.blade_count() as usize * 4)
        .unwrap();
    drop((pass, vertices, frame, dynamics, velocity, commands));
    finish(gpu);

    // The CPU: the same slots, tiles coming in started at their
    // quasi-static pose (the far field's iterations, as the GPU's).
    let per_tile = kept.per_tile;
    let mut cpu = GrassField::new(vec![Default::default(); stepped], dt)
        .unwrap()
        .with_colliders(colliders.to_vec());
    let mut held: Vec<Option<[i32; 2]>> = vec![None; kept.tile_count() as usize];
    let mut substeps = None;
    let mut entered = [0usize; 2];
    for (phase, eye) in eyes.iter().enumerate() {
        let wind = if phase == 0 { &calm } else { &strong };
        let mut start = 0;
        for axis in 0..3 {
            let n = field.vel[axis].len();
            field.vel[axis].copy_from_slice(&wind[start..start + n]);
            start += n;
        }
        let square = cover::kept_tiles(&cover, *eye);
        for n in 0..square.tile_count() as u32 {
            let tile = square.tile(n);
            let slot = cover::state_slot(tile, square.side) as usize;
            if held[slot] == Some(tile) {
                continue;
            }
            held[slot] = Some(tile);
            entered[phase] += 1;
            for index in 0..per_tile {
                let b =
                    cover::grass_blade(terrain, seed, &grass.shape, &grass.dynamics, tile, index)
                        .unwrap();
                let (angle, _) =
                    quasi_static_angles_within(&b, field.sample(b.rest_point(3)), FAR_ITERATIONS);
                let i = slot * per_tile as usize + index as usize;
                cpu.blades[i] = b;
                cpu.states[i] = GrassState {
                    angle,
                    velocity: [0.0; 4],
                };
                cpu.pressed[i] = Default::default();
            }
        }
        // The GPU's pass counts its substeps from the blades it was made
        // with, raised by any stiffer blade coming in.
        let needed = grass::substeps(&cpu.blades, dt).unwrap();
        let n = substeps.map_or(needed, |n: u32| n.max(needed));
        substeps = Some(n);
        cpu.substeps = n;
        for _ in 0..[30, 40][phase] {
            cpu.step(|x| field.sample(x));
        }
    }
    assert_eq!(entered, [25, 5], "tiles started in each phase");
    assert_eq!(
        Some(gpu_substeps),
        substeps,
        "substeps after the tiles came in"
    );
    let mut differs = 0.0f32;
    let mut swung = 0.0f32;
    for (g, c) in states.iter().zip(&cpu.states) {
        for m in 0..4 {
            differs = differs.max((g.angle[m] - c.angle[m]).abs());
            swung = swung.max(c.velocity[m].abs());
        }
    }
    eprintln!(
        "{stepped} kept blades: GPU and CPU angles within {differs:e} rad; swinging at up to {swung} rad/s"
    );
    assert!(swung > 0.1, "the blades barely swing: {swung} rad/s");
    assert!(differs < 1e-4, "GPU and CPU states differ by {differs} rad");
    if !colliders.is_empty() {
        let pressed_differs = presses
            .iter()
            .zip(&cpu.pressed)
            .map(|(g, c)| (g.pressed - c.pressed).abs())
            .fold(0.0f32, f32::max);
        let pressed = cpu.pressed.iter().filter(|p| p.pressed > 0.1).count();
        // How high each kept tip stands over its root, against its rest
        // height: the pressed blades' and the others' means.
        let mut lowered = [(0.0f32, 0usize); 2];
        for (i, pose) in cpu.poses().enumerate() {
            let b = &cpu.blades[i];
            let stands =
                (pose.points[3].y - b.rest_point(0).y) / (b.rest_point(3).y - b.rest_point(0).y);
            let k = (cpu.pressed[i].pressed > 0.1) as usize;
            lowered[k].0 += stands;
            lowered[k].1 += 1;
        }
        let [free, under] = lowered.map(|(sum, n)| sum / n.max(1) as f32);
        eprintln!(
            "{pressed} kept blades pressed over 0.1 (GPU and CPU pressed states within {pressed_differs:e}); \
             their tips stand at {under:.2} of their rest height, the others' at {free:.2}"
        );
        assert!(pressed >= 10, "{pressed} blades pressed");
        assert!(pressed_differs < 1e-5, "{pressed_differs}");
        assert!(under < free - 0.2, "pressed {under}, free {free}");
    } else {
        assert!(
            presses.is_empty(),
            "a pass made without colliders keeps pressed states"
        );
    }

    // The tile pass's pose, blade by blade: the simulated square's blades
    // from their state (their pressing faded out over the band inside the
    // radius), the others quasi-static.
    let r = cover.simulate_radius();
    let mut counts = [0usize; 3];
    let mut posed_pressed = 0;
    let mut worst = 0.0f32;
    for (n, (tile, index)) in tiles.blades().enumerate() {
        let b =
            cover::grass_blade(terrain, seed, &grass.shape, &grass.dynamics, tile, index).unwrap();
        let root = b.rest_point(0);
        let fade = cover::pressed_fade(r, Vec2::new(root.x, root.z).distance(eyes[1]));
        let k = [tile[0] - kept.origin[0], tile[1] - kept.origin[1]];
        let in_square = k.iter().all(|&a| (0..kept.side as i32).contains(&a));
        let (angle, pressed, kind) = if in_square {
            let slot = cover::state_slot(tile, kept.side);
            let kept = (slot * per_tile + index) as usize;
            let pressed = presses.get(kept).map_or(0.0, |p| p.pressed);
            (
                states[kept].angle,
                fade * pressed,
                1 + (fade >= 1.0) as usize,
            )
        } else {
            let (balance, _) =
                quasi_static_angles_within(&b, field.sample(b.rest_point(3)), FAR_ITERATIONS);
            let (still, _) = cover::held_above_ground(terrain, &b, balance);
            (still, 0.0, 0)
        };
        counts[kind] += 1;
        posed_pressed += (pressed > 0.01) as usize;
        let cpu_pose = grass::vertices(&b, &grass::pressed_pose(&b, angle, pressed));
        for (g, c) in posed[4 * n..4 * n + 4].iter().zip(&cpu_pose) {
            let at = |v: &BladeVertex| Vec3::from_slice(&v.position[..3]);
            worst = worst.max(at(g).distance(at(c)));
        }
    }
    eprintln!(
        "posed: {} quasi-static, {} from their state with their pressing faded, {} from their state ({posed_pressed} pressed); \
         GPU and CPU within {worst:e} m",
        counts[0], counts[1], counts[2]
    );
    assert!(counts.iter().all(|&c| c > 10), "{counts:?}");
    assert_eq!(
        posed_pressed > 0,
        !colliders.is_empty(),
        "{posed_pressed} posed pressed"
    );
    assert!(worst < 1e-4, "the tile pass's poses differ by {worst} m");
}

/// A cover seen from 5 m up while the camera flies along x at 10 m/s in a
/// turbulent wind, the paper's dynamics in the tiles reaching within 12 m.
fn band_scene() -> meadow::scene::Scene {
    let text = r#"name = "band"
seed = 3

[camera]
position = [0.0, 5.0, 0.0]
target = [12.0, 0.0, 0.0]
fov_y = 60.0

[[camera.path]]
time = 0.0
position = [0.0, 5.0, 0.0]
target = [12.0, 0.0, 0.0]

[[camera.path]]
time = 1.0
position = [0.0, 5.0, 0.0]
target = [12.0, 0.0, 0.0]

[[camera.path]]
time = 3.0
position = [20.0, 5.0, 0.0]
target = [32.0, 0.0, 0.0]

[light]
shadow_map = 512

[grass.cover]
density = 12.0
view_distance = 24.0
simulate_radius = 12.0

[wind]
cells = [48, 6, 48]
height = 3.0
window = [48.0, 48.0]
turbulence = { intensity = 0.5, length_scale = 3.0, seed = 4 }

[wind.inflow]
speed = 3.0
heading = 90.0
"#;
    meadow::scene::file::parse(text, "band.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// Issue 40, item 2, and issue 65, item 7: nothing pops where a cover
/// blade crosses the simulated square's edge, nor in the far field. Over a
/// flight at 10 m/s, 30 frames a second, each cover blade's tip is followed
/// from frame to frame (by its tile and index) and sorted by whether its
/// tile came into or left the simulated square between the two frames
/// (`cover::kept_tiles`), stayed in it, or stayed out. The crossing blades
/// move no more than those that stayed on either side (99th percentile
/// within a quarter over the larger). A far tip's motion changes from one
/// frame to the next (|x2 - 2 x1 + x0|: a pop of d shows as d, a smooth
/// motion as its acceleration times a frame squared) by no more than a
/// simulated blade's does, and at most 5 cm; and no far tip moves in a
/// frame (the kernel's own measure, report.json's) more than the fastest
/// simulated one. A far tip may move 5 cm in a frame in this wind (1.5
/// m/s), smoothly: the simulated blades reach 0.21 m.
/// Measured: crossing 0.0223 m (largest 0.048), in the square 0.0581 m
/// (0.208), beyond it 0.0197 m (0.053); the change of a tip's move at
/// most 0.084 m in the square, 0.0185 m beyond it. With the far blades
/// shown at their balance at once, as before their poses were kept
/// (`far_tracking` 0 by hand): beyond it 0.0712 m (0.834), the change
/// 1.02 m, fails; with a tile coming in started at its balance from rest
/// instead of its last pose (glsl/cover/enter.comp by hand), the crossing
/// blades 0.146 m, fails.
#[test]
fn nothing_pops_where_the_cover_crosses_the_simulated_square_nor_beyond() {
    use meadow::frame::FrameRecorder;
    use meadow::render::{FrameUniforms, ViewMode};
    use std::collections::HashMap;
    let scene = band_scene();
    let cover = scene.grass.cover.clone().unwrap();
    let seed = cover::seed32(scene.seed);
    let gpu = strict_gpu_with(None);
    let (w, h) = (160, 90);
    let mut recorder = FrameRecorder::new(&gpu, &scene, (w, h), 1, &[], Some(&[])).unwrap();
    // A second of wind first: the kept blades sway.
    recorder.simulate(60).unwrap();
    let mut frames = Vec::new();
    for n in 0..16 {
        let time = 1.0 + n as f32 / 30.0;
        let uniforms = FrameUniforms::new(&scene, w, h, ViewMode::Shaded, time);
        let steps = recorder.steps_until(time as f64).unwrap();
        recorder.render(&gpu, &uniforms, steps).unwrap();
        let all: Vec<BladeVertex> = recorder
            .blades()
            .buffer()
            .read_back(
                &gpu,
                recorder.commands(),
                recorder.blades().count() as usize * 4,
            )
            .unwrap();
        let (eye, _) = scene.camera.at(time);
        let eye = Vec2::new(eye.x, eye.z);
        let tiles = CoverTiles::around(&cover, eye);
        let rest = cover::vertices(&FLAT, seed, &scene.grass.shape, &tiles);
        // The tips of the blades posed (the others stand at rest: the
        // frame cannot draw them).
        let tips: HashMap<([i32; 2], u32), Vec3> = tiles
            .blades()
            .enumerate()
            .filter(|(n, _)| all[4 * n + 3].position != rest[4 * n + 3].position)
            .map(|(n, key)| (key, Vec3::from_slice(&all[4 * n + 3].position[..3])))
            .collect();
        frames.push((cover::kept_tiles(&cover, eye), tips));
    }
    let (far_jump, _) = recorder.cover_tip_jumps();
    drop(recorder);
    finish(gpu);

    let holds = |square: &CoverTiles, tile: [i32; 2]| {
        (0..2).all(|a| (0..square.side as i32).contains(&(tile[a] - square.origin[a])))
    };
    // Crossing, stayed in the square, stayed out.
    let mut moves: [Vec<f32>; 3] = Default::default();
    for pair in frames.windows(2) {
        let ((square_before, before), (square, after)) = (&pair[0], &pair[1]);
        for (key, tip) in after {
            let Some(was) = before.get(key) else { continue };
            let (was_in, is_in) = (holds(square_before, key.0), holds(square, key.0));
            let kind = if was_in != is_in {
                0
            } else if is_in {
                1
            } else {
                2
            };
            moves[kind].push(tip.distance(*was));
        }
    }
    // How abruptly a tip's motion changes: |x2 - 2 x1 + x0| over three
    // frames in a row (a pop of d shows as d; a smooth motion as its
    // acceleration times a frame squared), the largest of the blades that
    // stayed in the square and of those that stayed beyond it.
    let mut abrupt = [0.0f32; 2];
    for three in frames.windows(3) {
        for (key, x2) in &three[2].1 {
            let (Some(x1), Some(x0)) = (three[1].1.get(key), three[0].1.get(key)) else {
                continue;
            };
            let inside = three.iter().map(|(square, _)| holds(square, key.0));
            let kind = match inside.collect::<Vec<_>>()[..] {
                [true, true, true] => 0,
                [false, false, false] => 1,
                _ => continue,
            };
            abrupt[kind] = abrupt[kind].max((*x2 - 2.0 * *x1 + *x0).length());
        }
    }
    let counts = moves.each_ref().map(Vec::len);
    let [crossing, kept, far] = moves.map(|mut m| {
        m.sort_by(f32::total_cmp);
        let at = |q: f64| m.get(((m.len().max(1) - 1) as f64 * q) as usize).copied();
        (at(0.99).unwrap_or(0.0), at(1.0).unwrap_or(0.0))
    });
    eprintln!(
        "tips' move between frames, 99th percentile (largest): crossing the square's edge {:.4} m ({:.3}), in the square {:.4} m ({:.3}), beyond it {:.4} m ({:.3}); {counts:?} blade-pairs; the far field's largest as the kernel measured it {far_jump:.4} m; the largest change of a tip's move from one frame to the next: in the square {:.4} m, beyond it {:.4} m",
        crossing.0, crossing.1, kept.0, kept.1, far.0, far.1, abrupt[0], abrupt[1]
    );
    assert!(
        counts[0] > 100 && counts[1] > 1000 && counts[2] > 1000,
        "{counts:?}"
    );
    assert!(
        crossing.0 <= 1.25 * kept.0.max(far.0),
        "the crossing blades move {:.4} m in a frame (99th percentile), more than beside them ({:.4}, {:.4} m)",
        crossing.0,
        kept.0,
        far.0
    );
    assert!(
        (far_jump - far.1).abs() < 1e-4 || far_jump > far.1,
        "the kernel's largest far move {far_jump} m, the blades followed here {} m",
        far.1
    );
    assert!(
        abrupt[1] <= abrupt[0].min(0.05),
        "a far tip's move changed by {} m from one frame to the next (the simulated blades' by {} m at most)",
        abrupt[1],
        abrupt[0]
    );
    assert!(
        far_jump <= kept.1,
        "a far tip moved {far_jump} m in a frame, more than any simulated one ({} m)",
        kept.1
    );
}

/// The device memory a render holds does not grow with the cover's field:
/// a 100 m, a 1 km and an unbounded cover hold the same bytes (the issue
/// asks within 10%), while a meadow patch made once on the CPU holds more
/// the wider it is (what the measurement would see if the cover kept its
/// field).
#[test]
fn a_100_m_a_1_km_and_an_unbounded_cover_hold_the_same_device_memory() {
    use meadow::commands::render::render_to_dir;
    let dir = std::env::temp_dir().join(format!("meadow-cover-memory-{}", std::process::id()));
    let peak = |name: &str, scene: meadow::scene::Scene| {
        let request = common::strict_request(scene, 160, 90, 1, 1.0);
        let out = dir.join(name);
        let started = std::time::Instant::now();
        let report = render_to_dir(&request, &out).unwrap_or_else(|e| panic!("{name}: {e}"));
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap())
                .unwrap();
        let peak = json["device_memory"]["peak_bytes"]
            .as_u64()
            .expect("peak_bytes");
        let generated = json["blade_counts"]["generated"].as_u64().unwrap();
        assert_eq!(peak, report.device_memory.peak_bytes);
        eprintln!(
            "{name}: {:.2} MiB at peak, {generated} cover blades generated, {:.2} s for the render",
            peak as f64 / (1 << 20) as f64,
            started.elapsed().as_secs_f64()
        );
        (peak, generated)
    };
    let covered = |size: Option<[f32; 2]>| {
        let mut scene = covered_scene(false);
        scene.grass.cover.as_mut().unwrap().size = size;
        scene
    };
    let (hundred, hundred_blades) = peak("cover-100m", covered(Some([100.0, 100.0])));
    let (kilometre, _) = peak("cover-1km", covered(Some([1000.0, 1000.0])));
    let (unbounded, unbounded_blades) = peak("cover-unbounded", covered(None));
    // Around the origin, 10 m out, the 100 m field grows every blade.
    assert_eq!(hundred_blades, unbounded_blades);
    let patch = |side: f32| {
        let mut scene = covered_scene(false);
        scene.grass.cover = None;
        scene.grass.meadow.push(meadow::scene::Meadow {
            center: [0.0, 0.0],
            size: [side, side],
            count: None,
            density: Some(3.0),
            mask: None,
            mask_map: None,
        });
        scene
    };
    let (patch_100, _) = peak("meadow-100m", patch(100.0));
    let (patch_200, _) = peak("meadow-200m", patch(200.0));
    let _ = std::fs::remove_dir_all(&dir);
    let (least, most) = (
        hundred.min(kilometre).min(unbounded),
        hundred.max(kilometre).max(unbounded),
    );
    assert!(
        most as f64 <= 1.1 * least as f64,
        "covers of 100 m, 1 km and no bounds: {hundred}, {kilometre} and {unbounded} bytes"
    );
    assert!(
        patch_200 as f64 > 1.5 * patch_100 as f64,
        "meadow patches of 100 and 200 m: {patch_100} and {patch_200} bytes"
    );
}

/// A tile coming into the simulated square with a blade stiffer than any
/// stepped so far raises the substeps for all, so explicit Euler stays
/// stable for it (`model::grass::substeps`); they never fall. Over a
/// flight of 60 tiles with a wide stiffness range, the GPU pass's
/// substeps are the CPU's count over every blade kept so far, at each
/// move (fails with the count left at the first square's).
#[test]
fn a_stiffer_blade_coming_in_raises_the_substeps() {
    use meadow::compute::wind_pass::WindInput;
    use meadow::compute::CoverDynamics;
    use meadow::model::grass;
    use meadow::scene::GrassDynamics;

    // One blade a tile, 3 x 3 tiles kept.
    let cover = Cover {
        density: Some(0.07),
        view_distance: 8.0,
        seed: Some(5),
        simulate_radius: Some(2.0),
        size: None,
        center: None,
    };
    let grass = Grass {
        dynamics: GrassDynamics {
            tip_stiffness: [5e-3, 0.2],
            ..GrassDynamics::default()
        },
        ..Grass::default()
    };
    let seed = cover::seed32(5);
    let dt = 1.0 / 60.0;
    let (grid, _, calm) = steady_wind(Vec3::new(-16.0, 0.0, -16.0), 40.0);
    let gpu = strict_gpu_with(None);
    let commands = CommandPool::new(&gpu, "cover substeps commands").unwrap();
    let velocity = wind_buffer(&gpu, &commands, &calm);
    let input = WindInput {
        grid,
        velocity: &velocity,
        canopy: None,
        subgrid: None,
    };
    let eye = |n: usize| Vec2::new(0.5 + 4.0 * n as f32, 0.5);
    let setup = meadow::compute::cover_dynamics::CoverDynamicsSetup {
        cover: &cover,
        seed,
        grass: &grass,
        dt,
        camera: eye(0),
        terrain: &FLAT,
        colliders: &[],
    };
    let mut dynamics = CoverDynamics::new(&gpu, &commands, setup, &input).unwrap();
    let kept_blades = |camera: Vec2| -> Vec<grass::GrassBlade> {
        let square = cover::kept_tiles(&cover, camera);
        square
            .blades()
            .map(|(tile, index)| {
                cover::grass_blade(&FLAT, seed, &grass.shape, &grass.dynamics, tile, index).unwrap()
            })
            .collect()
    };
    let first = grass::substeps(&kept_blades(eye(0)), dt).unwrap();
    assert_eq!(dynamics.grass().substeps(), first);
    let mut expected = first;
    let rec = commands.begin().unwrap();
    for n in 1..=60 {
        dynamics.record_follow(&rec, eye(n)).unwrap();
        dynamics.record_step(&rec, meadow::model::contact::step_end_time(n as u64, dt));
        expected = expected.max(grass::substeps(&kept_blades(eye(n)), dt).unwrap());
        assert_eq!(dynamics.grass().substeps(), expected, "after move {n}");
    }
    rec.submit_and_wait("cover flight").unwrap();
    let states = dynamics.grass().read_states(&gpu, &commands).unwrap();
    drop((dynamics, velocity, commands));
    finish(gpu);
    eprintln!("substeps: {first} for the first square, {expected} after the flight");
    assert!(
        expected > first,
        "no blade came in stiffer: the test tells nothing"
    );
    assert!(
        states.iter().flat_map(|s| s.angle).all(|a| a.is_finite()),
        "a kept blade's state is not finite"
    );
}
