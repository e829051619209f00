//! One frame's passes and barriers in words (src/gpu/journal.rs), held to
//! tests/snapshots/frame_journal.txt: the wind step's kernels, the grass
//! step's with a collider (its binning and the kernel over the blades it
//! touches, dispatched indirectly), the cull pass, the shadow and colour
//! passes and the read-back, each with what it declared and the barriers
//! and layout transitions that followed. A change to what a pass declares,
//! or to the barriers the tracker derives, shows here as a diff to read;
//! after a deliberate one, `MEADOW_BLESS=1 scripts/test --test
//! frame_journal` writes the snapshot anew.

use crate::common;

use common::{finish, strict_gpu};
use meadow::frame::FrameRecorder;
use meadow::render::{FrameUniforms, ViewMode};
use meadow::scene::{field, Scene};

const SNAPSHOT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/snapshots/frame_journal.txt"
);

#[test]
fn one_frame_s_passes_and_barriers_match_the_snapshot() {
    // roll's ball among 2,000 blades, culled, shadowed, one step before
    // its frame at 0.5 s.
    let mut scene = Scene::builtin("roll").unwrap();
    scene.set_blade_count(2000).unwrap();
    scene.light.shadow_map = 512;
    let blades = scene.field().unwrap();
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed).unwrap();
    let gpu = strict_gpu();
    let (w, h) = (64, 48);
    let mut recorder =
        FrameRecorder::new(&gpu, &scene, (w, h), 1, &blades, Some(&dynamic)).unwrap();
    let uniforms = FrameUniforms::new(&scene, w, h, ViewMode::Shaded, 0.5);
    recorder.commands().journal().start();
    recorder.render(&gpu, &uniforms, 1).unwrap();
    let lines = recorder.commands().journal().take();
    drop(recorder);
    finish(gpu);

    let text = lines.join("\n") + "\n";
    assert!(
        text.contains("barrier:") && text.contains("transition:") && text.contains("submit:"),
        "{text}"
    );
    if std::env::var_os("MEADOW_BLESS").is_some() {
        std::fs::write(SNAPSHOT, &text).unwrap();
        return;
    }
    let held = std::fs::read_to_string(SNAPSHOT).unwrap_or_default();
    if held != text {
        let new = std::env::temp_dir().join("frame_journal.txt");
        std::fs::write(&new, &text).unwrap();
        let first = held
            .lines()
            .zip(text.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(held.lines().count().min(text.lines().count()));
        panic!(
            "the frame's journal differs from {SNAPSHOT} from line {} on (this run's: {}; diff them, and after a deliberate change set MEADOW_BLESS=1)",
            first + 1,
            new.display()
        );
    }
}
