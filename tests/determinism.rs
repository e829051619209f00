//! Same scene, same seed, same device: byte-identical frames, the wind and
//! grass simulation included.

use crate::common;

use common::sim::SimRig;
use meadow::commands::render::{render_to_dir, RenderRequest};
use meadow::scene::Scene;

#[test]
fn same_scene_and_seed_give_byte_identical_png() {
    let mut scene = Scene::builtin("fig10-several-bunches").unwrap();
    scene.set_blade_count(2000).unwrap();
    scene.wind.cells = common::COARSE_WIND_CELLS;
    // Two frames of a swaying field: 0.5 s and 1.0 s into the wind.
    let mut request = common::strict_request(scene, 320, 200, 2, 2.0);
    request.msaa = 8;
    request.animation.start = 0.5;
    let dir = std::env::temp_dir().join(format!("meadow-determinism-{}", std::process::id()));
    let a = render_to_dir(&request, &dir.join("a")).expect("first render");
    let b = render_to_dir(&request, &dir.join("b")).expect("second render");
    assert_eq!(a.validation.errors + b.validation.errors, 0);
    assert_eq!(a.sim_steps, 60);
    for name in ["frame_0000.png", "frame_0001.png"] {
        let png_a = std::fs::read(dir.join("a").join(name)).unwrap();
        let png_b = std::fs::read(dir.join("b").join(name)).unwrap();
        assert!(
            png_a == png_b,
            "two renders of the same scene differ at {name}"
        );
    }
    let png_a = std::fs::read(dir.join("a/frame_0000.png")).unwrap();

    // A different seed grows a different field: the check above can fail
    // (its first frame is enough to show it).
    let mut other = request.clone();
    other.scene.seed += 1;
    other.animation.frames = 1;
    render_to_dir(&other, &dir.join("c")).expect("third render");
    let png_c = std::fs::read(dir.join("c/frame_0000.png")).unwrap();
    assert!(png_a != png_c, "a different seed rendered the same picture");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The frame rate and the number of frames choose which moments become
/// pictures; they do not change the simulation. The moment t = 1 s is the
/// same picture whether it is frame 1 at 1 fps or frame 4 at 4 fps.
#[test]
fn the_frame_rate_does_not_change_the_simulation() {
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.light.shadow_map = 1024;
    scene.wind.cells = common::COARSE_WIND_CELLS;
    let request = |frames: u32, fps: f32| RenderRequest {
        gif: false,
        video: None,
        overwrite: false,
        light_waves: false,
        ..common::strict_request(scene.clone(), 160, 90, frames, fps)
    };
    let dir = std::env::temp_dir().join(format!("meadow-frame-rate-{}", std::process::id()));
    let slow = render_to_dir(&request(2, 1.0), &dir.join("slow")).expect("1 fps");
    let fast = render_to_dir(&request(5, 4.0), &dir.join("fast")).expect("4 fps");
    assert_eq!(slow.sim_steps, 60);
    assert_eq!(fast.sim_steps, 60, "the same fixed steps to reach 1 s");
    let at_one_second = [
        std::fs::read(dir.join("slow/frame_0001.png")).unwrap(),
        std::fs::read(dir.join("fast/frame_0004.png")).unwrap(),
    ];
    assert!(
        at_one_second[0] == at_one_second[1],
        "t = 1 s differs between 1 fps and 4 fps"
    );
    // The check can fail: t = 0.75 s is a different picture.
    let earlier = std::fs::read(dir.join("fast/frame_0003.png")).unwrap();
    assert!(earlier != at_one_second[1]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two runs of the simulation of the same scene and seed on the same
/// device leave byte-identical blade state (angles, angular velocities),
/// control points and wind after 120 steps of a rotating wind (on a
/// coarser wind grid than the scene's, for time).
#[test]
fn same_scene_and_seed_give_identical_blade_and_wind_state() {
    let gpu = common::strict_gpu();
    let mut scene = Scene::builtin("fig11-meadow-rotating").unwrap();
    scene.set_blade_count(3000).unwrap();
    scene.wind.cells = [24, 10, 24];
    let run = |scene: &Scene| {
        let mut rig = SimRig::new(&gpu, scene);
        rig.run(120);
        let state = (
            bytemuck::cast_slice::<_, u8>(&rig.states(&gpu)).to_vec(),
            bytemuck::cast_slice::<_, u8>(&rig.vertices(&gpu)).to_vec(),
            rig.velocity(&gpu).concat(),
        );
        drop(rig);
        state
    };
    let (states_a, vertices_a, wind_a) = run(&scene);
    let (states_b, vertices_b, wind_b) = run(&scene);
    assert!(states_a == states_b, "blade states differ between two runs");
    assert!(vertices_a == vertices_b, "control points differ");
    assert!(
        wind_a
            .iter()
            .zip(&wind_b)
            .all(|(a, b)| a.to_bits() == b.to_bits()),
        "wind differs"
    );
    // The grass really moved, and another seed is another state: the
    // comparison can fail.
    assert!(states_a.iter().any(|&b| b != 0), "the grass never moved");
    let mut other = scene.clone();
    other.seed += 1;
    let (states_c, _, _) = run(&other);
    assert!(states_a != states_c, "a different seed gave the same state");
    common::finish(gpu);
}

/// Several pictures of one simulation (`render_pictures`, as `reproduce`
/// draws a figure's shaded and motion views) are, byte for byte, the
/// frames each view rendered alone gives: the simulation steps once per
/// frame, not once per picture.
#[test]
fn pictures_of_one_simulation_are_the_frames_of_each_view_alone() {
    use meadow::commands::render::{render_pictures, Picture};
    use meadow::scene::ViewMode;
    // Two frames, 0.1 s and 0.2 s into the wind (12 steps), on a coarser
    // wind grid than the scene's, for time.
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.light.shadow_map = 1024;
    scene.wind.cells = [24, 10, 24];
    let mut request = common::strict_request(scene, 160, 90, 2, 10.0);
    request.animation.start = 0.1;
    let dir = std::env::temp_dir().join(format!("meadow-pictures-{}", std::process::id()));
    let views = [ViewMode::Shaded, ViewMode::Motion];
    let pictures: Vec<Picture> = views
        .iter()
        .map(|&view| Picture {
            view,
            dir: dir.join(format!("together-{view:?}")),
        })
        .collect();
    let together = render_pictures(&request, &pictures, &mut |_| true).expect("two pictures");
    assert_eq!(together.len(), 2);
    for (view, report) in views.iter().zip(&together) {
        assert_eq!(report.view, *view);
        assert_eq!(
            report.sim_steps, 12,
            "one simulation to 0.2 s, not one per picture"
        );
        assert_eq!(report.validation.errors, 0);
        let alone = dir.join(format!("alone-{view:?}"));
        render_to_dir(
            &RenderRequest {
                view: *view,
                ..request.clone()
            },
            &alone,
        )
        .expect("one view alone");
        let together = dir.join(format!("together-{view:?}"));
        for name in ["frame_0000.png", "frame_0001.png", "animation.gif"] {
            let a = std::fs::read(together.join(name)).unwrap();
            let b = std::fs::read(alone.join(name)).unwrap();
            assert!(
                a == b,
                "{view:?} {name} differs from the view rendered alone"
            );
        }
        assert!(together.join("report.json").is_file() && together.join("scene.toml").is_file());
    }
    // The views differ: the comparison above is of two pictures.
    let shaded = std::fs::read(dir.join("together-Shaded/frame_0001.png")).unwrap();
    let motion = std::fs::read(dir.join("together-Motion/frame_0001.png")).unwrap();
    assert!(shaded != motion);
    let _ = std::fs::remove_dir_all(&dir);
}
