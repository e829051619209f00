//! The cull pass (src/render/cull.rs) on the default device, validation
//! on: its lists against the CPU reference (src/render/visibility.rs) on
//! blades the wind has bent, and frames drawn from the lists against
//! frames drawing every blade.

mod common;

use common::{finish, strict_gpu};
use glam::{Mat4, Vec3, Vec4};
use meadow::frame::{Frame, FrameRecorder};
use meadow::render::visibility::visibility;
use meadow::render::{FrameUniforms, ViewMode};
use meadow::scene::{field, Scene};
use meadow::sim::BladeVertex;

/// A decision the GPU may take the other way from the CPU: the box touches
/// a plane to within float rounding (plane units are clip-space w, metres
/// at the scale of these scenes).
const ROUNDING: f32 = 1e-4;

fn recorder(gpu: &meadow::gpu::Gpu, scene: &Scene, size: (u32, u32)) -> FrameRecorder {
    let blades = scene.field().unwrap();
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed).unwrap();
    FrameRecorder::new(gpu, scene, size, 4, &blades, Some(&dynamic)).unwrap()
}

/// Frames at `times` (simulated seconds), each with the steps up to it.
fn frames(gpu: &meadow::gpu::Gpu, scene: &Scene, size: (u32, u32), times: &[f64]) -> Vec<Frame> {
    let mut r = recorder(gpu, scene, size);
    times
        .iter()
        .map(|&t| {
            let steps = r.steps_until(t).unwrap();
            let u = FrameUniforms::new(scene, size.0, size.1, ViewMode::Shaded, t as f32);
            r.render(gpu, &u, steps).unwrap()
        })
        .collect()
}

#[test]
fn the_lists_are_the_cpu_references_on_bent_blades_in_blade_order() {
    let gpu = strict_gpu();
    let mut scene = Scene::builtin("table1").unwrap();
    scene.set_blade_count(30_000).unwrap();
    scene.set_shadow_map(512).unwrap();
    scene.cull.enabled = true;
    let size = (160, 90);
    let mut r = recorder(&gpu, &scene, size);
    // Two seconds of wind: the blades lean, so their bounds are not the
    // rest shape's.
    let t = 2.0;
    let steps = r.steps_until(t).unwrap();
    let uniforms = FrameUniforms::new(&scene, size.0, size.1, ViewMode::Shaded, t as f32);
    let frame = r.render(&gpu, &uniforms, steps).unwrap();
    let counts = frame.cull.expect("culling is on");
    let n = r.blades().count() as usize;
    assert_eq!(counts.blades as usize, n);

    let vertices: Vec<BladeVertex> = r
        .blades()
        .buffer()
        .read_back(&gpu, r.commands(), 4 * n)
        .unwrap();
    let cull = r.cull().unwrap();
    let color = cull.read_color_list(&gpu, r.commands()).unwrap();
    let shadow = cull.read_shadow_list(&gpu, r.commands()).unwrap();
    assert_eq!(color.len(), counts.in_view as usize);
    assert_eq!(shadow.len(), counts.shadow_casters as usize);
    for list in [&color, &shadow] {
        assert!(
            list.windows(2).all(|w| w[0] < w[1]),
            "a list is out of blade order"
        );
    }

    let view_proj = Mat4::from_cols_array(&uniforms.view_proj);
    let light = Vec4::from(uniforms.light_dir).truncate();
    let (mut in_view, mut casters, mut leaning) = (0, 0, 0);
    let mut disagree = 0;
    for (b, v) in vertices.chunks_exact(4).enumerate() {
        let v: &[BladeVertex; 4] = v.try_into().unwrap();
        let (seen, margin) = visibility(v, &view_proj, light, true);
        let gpu_seen = (
            color.binary_search(&(b as u32)).is_ok(),
            shadow.binary_search(&(b as u32)).is_ok(),
        );
        if gpu_seen != (seen.in_view, seen.caster) {
            assert!(
                margin < ROUNDING,
                "blade {b}: GPU (in view, caster) {gpu_seen:?}, CPU {seen:?} by a margin of {margin}"
            );
            disagree += 1;
        }
        in_view += seen.in_view as usize;
        casters += seen.caster as usize;
        let tip = Vec4::from(v[3].position).truncate() - Vec4::from(v[0].position).truncate();
        leaning += (tip.normalize().dot(Vec3::Y) < 0.95) as usize;
    }
    eprintln!(
        "{n} blades: {in_view} in view, {casters} casters, {leaning} leaning > 18 deg, {disagree} rounding disagreements"
    );
    // The test means something: both lists leave blades out and keep
    // some, the shadow list keeps blades the view does not, and the wind
    // has bent the blades.
    assert!(
        in_view > n / 10 && in_view < n * 9 / 10,
        "{in_view} of {n} in view"
    );
    assert!(casters > in_view && casters < n, "{casters} casters");
    assert!(leaning > n / 10, "only {leaning} of {n} blades lean");
    assert!(disagree <= n / 1000, "{disagree} disagreements");
    drop(r);
    finish(gpu);
}

#[test]
fn culling_changes_no_pixel() {
    let gpu = strict_gpu();
    // The default scene (the camera inside the field, a quarter of it
    // behind, the sun's shadows falling in from outside the view's sides)
    // and Fig. 13 seen from its own camera, each with the wind moving.
    for name in ["table1", "fig13-obstacles"] {
        let mut scene = Scene::builtin(name).unwrap();
        scene.set_shadow_map(2048).unwrap();
        let times = [0.0, 0.5];
        scene.cull.enabled = true;
        let culled = frames(&gpu, &scene, (320, 180), &times);
        scene.cull.enabled = false;
        let all = frames(&gpu, &scene, (320, 180), &times);
        for (i, (c, a)) in culled.iter().zip(&all).enumerate() {
            let counts = c.cull.unwrap();
            assert!(counts.in_view < counts.blades, "{name}: nothing was culled");
            assert!(a.cull.is_none());
            let differ = c
                .rgba
                .chunks_exact(4)
                .zip(a.rgba.chunks_exact(4))
                .filter(|(p, q)| p != q)
                .count();
            assert_eq!(
                differ, 0,
                "{name} frame {i}: {differ} pixels differ with culling ({counts:?})"
            );
        }
    }
    finish(gpu);
}
