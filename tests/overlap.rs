//! The simulation beside the drawing (`render.overlap`, src/frame/ahead.rs)
//! on the default device, validation with synchronization on: a frame's
//! steps in a submission of their own, ordered by timeline semaphores,
//! give the frames the one-submission path gives. On lavapipe, which has
//! one queue, the submissions run in order on it; a device with a second
//! queue runs the same test with the steps on it.

use crate::common;

use common::{finish, strict_gpu};
use meadow::frame::{Frame, FrameRecorder};
use meadow::gpu::Gpu;
use meadow::render::{FrameUniforms, ViewMode};
use meadow::scene::{field, Overlap, Scene};

const SIZE: (u32, u32) = (160, 90);
/// Steps a frame: 2 FPS at the scene's 60 steps a second, each frame
/// 30 steps of a swaying field.
const STEPS: u64 = 30;
const FRAMES: u64 = 4;

/// Fig. 10's few bunches swaying, culled (the cull pass reads the drawn
/// blades on the graphics side too), with `overlap`.
fn scene(overlap: Overlap) -> Scene {
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.set_shadow_map(512).unwrap();
    // The same submissions in the same order.
    scene.wind.cells = common::COARSE_WIND_CELLS;
    scene.cull.enabled = true;
    scene.render.overlap = overlap;
    scene
}

fn recorder(gpu: &Gpu, scene: &Scene) -> FrameRecorder {
    let blades = scene.field().unwrap();
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed).unwrap();
    FrameRecorder::new(gpu, scene, SIZE, 1, &blades, Some(&dynamic)).unwrap()
}

fn uniforms(scene: &Scene, frame: u64) -> FrameUniforms {
    let t = (frame * STEPS) as f32 / 60.0;
    FrameUniforms::new(scene, SIZE.0, SIZE.1, ViewMode::Shaded, t)
}

/// The frames of the one-submission path: steps then drawing.
fn in_one_submission(gpu: &Gpu) -> Vec<Frame> {
    let scene = scene(Overlap::Off);
    let mut recorder = recorder(gpu, &scene);
    assert_eq!(recorder.overlap(), "off");
    (1..=FRAMES)
        .map(|f| recorder.render(gpu, &uniforms(&scene, f), STEPS).unwrap())
        .collect()
}

fn assert_same(a: &[Frame], b: &[Frame], what: &str) {
    assert_eq!(a.len(), b.len());
    for (f, (a, b)) in a.iter().zip(b).enumerate() {
        let differing = a
            .rgba
            .chunks_exact(4)
            .zip(b.rgba.chunks_exact(4))
            .filter(|(p, q)| p != q)
            .count();
        assert_eq!(
            differing, 0,
            "{what}: frame {f} differs in {differing} pixels"
        );
    }
}

/// Each frame's steps submitted beside the drawing of the frame before
/// (`render_then`), the drawing waiting for their copy into the drawn
/// blades: the same frames, byte for byte, as steps and drawing in one
/// submission, with the steps' GPU time still reported. The frames move
/// (the first and the last differ), so a copy left out, or a frame drawn
/// from the steps of the frame before, fails it. (Broken by hand on
/// lavapipe, the copy left out: the first frame showed the rest pose,
/// 2,076 of its 14,400 pixels differing.)
#[test]
fn the_steps_beside_the_drawing_draw_the_same_frames() {
    let gpu = strict_gpu();
    let expected = in_one_submission(&gpu);
    assert!(
        expected[0].rgba != expected[FRAMES as usize - 1].rgba,
        "the field does not move: the comparison could not fail"
    );

    let scene = scene(Overlap::On);
    let mut recorder = recorder(&gpu, &scene);
    let queues = if gpu.has_simulation_queue() {
        "two queues"
    } else {
        "one queue"
    };
    assert_eq!(recorder.overlap(), queues);
    let beside: Vec<Frame> = (1..=FRAMES)
        .map(|f| {
            let next = if f < FRAMES { STEPS } else { 0 };
            recorder
                .render_then(&gpu, &uniforms(&scene, f), STEPS, next)
                .unwrap()
        })
        .collect();
    assert_same(&expected, &beside, "the steps beside the drawing");
    if let Some(t) = beside[1].timings {
        assert!(
            t.wind > 0.0 && t.grass > 0.0,
            "the steps' time is not reported: {t:?}"
        );
    }
    drop(recorder);

    // The same through the frame's breaks (a stop asked between its
    // submissions) and the steps run ahead in a batch of their own.
    let mut recorder = self::recorder(&gpu, &scene);
    let mut go = || true;
    let mut broken = Vec::new();
    for f in 1..=FRAMES {
        let u = uniforms(&scene, f);
        let frame = if f % 2 == 1 {
            recorder
                .render_unless_stopped(&gpu, &u, STEPS, Some(&mut go))
                .unwrap()
        } else {
            recorder.simulate(STEPS - 1).unwrap();
            recorder.render_unless_stopped(&gpu, &u, 1, None).unwrap()
        };
        broken.push(frame.expect("not stopped"));
    }
    assert_same(&expected, &broken, "with breaks and batches");

    // A frame asking for other steps than were sent ahead for it is
    // refused, not drawn at the wrong moment.
    recorder
        .render_then(&gpu, &uniforms(&scene, 5), STEPS, 5)
        .unwrap();
    let refused = recorder
        .render(&gpu, &uniforms(&scene, 6), STEPS)
        .err()
        .unwrap();
    assert!(refused.to_string().contains("simulated ahead"), "{refused}");
    drop(recorder);
    finish(gpu);
}

/// A cover's tiles read the wind the next steps would write beside the
/// drawing: "on" is refused before anything is made, "auto" stays on one
/// submission.
#[test]
fn a_cover_stays_in_one_submission() {
    let gpu = strict_gpu();
    let mut scene = Scene::builtin("steppe").unwrap();
    scene.render.overlap = Overlap::On;
    let refused = FrameRecorder::new(&gpu, &scene, SIZE, 1, &[], Some(&[]))
        .err()
        .expect("refused");
    let message = refused.to_string();
    assert!(
        message.contains("render.overlap") && message.contains("[grass.cover]"),
        "{message}"
    );
    finish(gpu);
}
