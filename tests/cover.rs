//! The cover (`[grass.cover]`): tiles of blades made on the GPU around the
//! camera (glsl/cover/tiles.comp) against the CPU reference
//! (src/scene/cover/), bit for bit, on the default device with
//! validation on; what a frame makes, its bounds and its memory. Its poses:
//! tests/cover_pose.rs; its dynamics near the camera:
//! tests/cover_dynamics.rs.

use crate::common;

use common::cover::*;
use common::{finish, strict_gpu_with};
use glam::Vec2;
use glam::Vec3;
use meadow::model::BladeVertex;
use meadow::scene::cover::{self, CoverTiles};
use meadow::scene::{BladeShape, Cover};

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
        let m = glam::Mat4::from_cols_array_2d(view_proj);
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
