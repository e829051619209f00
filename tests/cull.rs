//! The cull pass (src/render/cull.rs) on the default device, validation
//! on: its lists against the CPU reference (src/render/visibility.rs) on
//! blades the wind has bent, and frames drawn from the lists against
//! frames drawing every blade.

mod common;

use common::{finish, strict_gpu};
use glam::{Mat4, Vec3, Vec4};
use meadow::frame::{Frame, FrameRecorder};
use meadow::render::thinning::Thinning;
use meadow::render::visibility::thinned_visibility;
use meadow::render::{FrameUniforms, ViewMode};
use meadow::scene::{field, Scene};
use meadow::sim::BladeVertex;

/// A decision the GPU may take the other way from the CPU: the box touches
/// a plane to within float rounding (plane units are clip-space w, metres
/// at the scale of these scenes).
const ROUNDING: f32 = 1e-4;
/// The same for the distance thinning: a blade's h lies at the top of
/// the band to within float rounding (a share of the band's top).
const THINNING_ROUNDING: f32 = 1e-5;

// The distance thinning against the same frame without it (table1's field
// and camera with 20,000 blades, 480 x 270, t = 0.5 s). Measured on
// lavapipe: far third mean FLIP 0.059, its mean colour moved by 0.88 (of
// 255) in the channel that moved most, the near rows 0.0000. With the
// widening removed by hand: 0.066 and 3.55, the colour test fails.
const FAR_FLIP: f64 = 0.08;
const FAR_COLOUR_SHIFT: f64 = 2.0;
const NEAR_FLIP: f64 = 0.002;

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
    let eye = Vec4::from(uniforms.camera_pos).truncate();
    let thinning = Thinning::of(&scene);
    assert!(thinning.is_on(), "the default scene thins by distance");
    let (mut in_view, mut casters, mut leaning, mut kept) = (0, 0, 0, 0);
    let mut disagree = 0;
    for (b, v) in vertices.chunks_exact(4).enumerate() {
        let v: &[BladeVertex; 4] = v.try_into().unwrap();
        let (seen, margin, thin_margin) =
            thinned_visibility(v, &view_proj, light, true, &thinning, eye);
        let gpu_seen = (
            color.binary_search(&(b as u32)).is_ok(),
            shadow.binary_search(&(b as u32)).is_ok(),
        );
        if gpu_seen != (seen.in_view, seen.caster) {
            assert!(
                margin < ROUNDING || thin_margin < THINNING_ROUNDING,
                "blade {b}: GPU (in view, caster) {gpu_seen:?}, CPU {seen:?} by a margin of {margin} \
                 (thinning's {thin_margin})"
            );
            disagree += 1;
        }
        let root = Vec4::from(v[0].position);
        kept += (thinning.scale(root.truncate(), root.w, eye).0 > 0.0) as usize;
        in_view += seen.in_view as usize;
        casters += seen.caster as usize;
        let tip = Vec4::from(v[3].position).truncate() - Vec4::from(v[0].position).truncate();
        leaning += (tip.normalize().dot(Vec3::Y) < 0.95) as usize;
    }
    eprintln!(
        "{n} blades: {kept} left by thinning, {in_view} in view, {casters} casters, {leaning} leaning > 18 deg, \
         {disagree} rounding disagreements"
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
    // The thinning drops blades, and the GPU's count of those it keeps is
    // the CPU's (to within the rounding disagreements).
    assert!(
        kept < n * 9 / 10 && kept > n / 10,
        "thinning kept {kept} of {n}"
    );
    assert!(
        (counts.thinned_to as i64 - kept as i64).unsigned_abs() as usize <= disagree,
        "GPU kept {}, CPU {kept}",
        counts.thinned_to
    );
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
        // Frustum and caster culling only: the distance thinning changes
        // the far meadow on purpose (measured below).
        scene.cull.thin_from = 0.0;
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

/// Mean of `values` over the rows `rows` of a `width`-wide image.
fn rows_mean(values: &[f32], width: usize, rows: std::ops::Range<usize>) -> f64 {
    let part = &values[rows.start * width..rows.end * width];
    part.iter().map(|&v| v as f64).sum::<f64>() / part.len() as f64
}

/// Mean sRGB colour (0..255 per channel) of the rows `rows`.
fn rows_colour(rgba: &[u8], width: usize, rows: std::ops::Range<usize>) -> [f64; 3] {
    let part = &rgba[rows.start * width * 4..rows.end * width * 4];
    let n = (part.len() / 4) as f64;
    let mut sum = [0.0; 3];
    for p in part.chunks_exact(4) {
        for c in 0..3 {
            sum[c] += p[c] as f64;
        }
    }
    sum.map(|s| s / n)
}

#[test]
fn distance_thinning_keeps_the_far_meadow() {
    let gpu = strict_gpu();
    let mut scene = Scene::builtin("table1").unwrap();
    scene.set_shadow_map(2048).unwrap();
    // 22 blades per square metre: sparse enough that the far meadow's
    // coverage is not saturated, so blades thinned out and not made up
    // for by the widening show as soil (at table1's own 222 per square
    // metre 1 blade in 8 still covers it).
    scene.set_blade_count(20_000).unwrap();
    let size = (480u32, 270u32);
    let t = [0.5];
    assert!(Thinning::of(&scene).is_on());
    let thinned = frames(&gpu, &scene, size, &t).remove(0);
    scene.cull.thin_from = 0.0;
    let full = frames(&gpu, &scene, size, &t).remove(0);
    let counts = thinned.cull.unwrap();
    let counts_full = full.cull.unwrap();
    assert!(counts.thinned_to < counts.blades && counts_full.thinned_to == counts_full.blades);

    // The grass fills the frame from the row of the field's far edge
    // down; its far third is the third of those rows nearest the edge.
    let u = FrameUniforms::new(&scene, size.0, size.1, ViewMode::Shaded, t[0] as f32);
    let (lo, hi) = scene.grass_bounds();
    let edge =
        Mat4::from_cols_array(&u.view_proj) * Vec4::new((lo[0] + hi[0]) / 2.0, 0.0, lo[1], 1.0);
    let edge_row = ((edge.y / edge.w * 0.5 + 0.5) * size.1 as f32).max(0.0) as usize;
    let (w, h) = (size.0 as usize, size.1 as usize);
    let far = edge_row..edge_row + (h - edge_row) / 3;
    let near = far.end..h;

    let rgb = |f: &Frame| -> Vec<u8> {
        f.rgba
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect()
    };
    let a = nv_flip::FlipImageRgb8::with_data(size.0, size.1, &rgb(&full));
    let b = nv_flip::FlipImageRgb8::with_data(size.0, size.1, &rgb(&thinned));
    let error = nv_flip::flip(a, b, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec();
    let (flip_far, flip_near) = (
        rows_mean(&error, w, far.clone()),
        rows_mean(&error, w, near.clone()),
    );
    let (colour_full, colour_thinned) = (
        rows_colour(&full.rgba, w, far.clone()),
        rows_colour(&thinned.rgba, w, far.clone()),
    );
    let shift = (0..3)
        .map(|c| (colour_thinned[c] - colour_full[c]).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "thinning kept {} of {} blades ({} in view, {} without); far third rows {far:?}: mean FLIP {flip_far:.4}, \
         mean colour {colour_thinned:.1?} vs {colour_full:.1?} (largest channel shift {shift:.2}); \
         near rows {near:?}: mean FLIP {flip_near:.4}",
        counts.thinned_to, counts.blades, counts.in_view, counts_full.in_view
    );
    assert!(
        counts.in_view * 10 < counts_full.in_view * 7,
        "thinning left {} of {} in view",
        counts.in_view,
        counts_full.in_view
    );
    assert!(flip_far < FAR_FLIP, "far third: mean FLIP {flip_far}");
    assert!(
        shift < FAR_COLOUR_SHIFT,
        "far third: mean colour moved by {shift}"
    );
    assert!(
        flip_near < NEAR_FLIP,
        "near two thirds: mean FLIP {flip_near}"
    );
    finish(gpu);
}
