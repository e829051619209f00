//! The render pipeline on the default device (lavapipe when there is no
//! GPU), with validation on and zero errors asserted in every test.

use crate::common;

use common::{finish, mean_rgb, pixel, project, render, strict_gpu};
use glam::Vec3;
use meadow::model::{Blade, BladeKind};
use meadow::render::ViewMode;
use meadow::scene::{field, Meadow, Scene};

fn meadow_scene() -> Scene {
    Scene::builtin("table1").unwrap()
}

fn is_grass(p: [u8; 3]) -> bool {
    let [r, g, b] = p.map(i32::from);
    g > r && g > b + 10
}

#[test]
fn meadow_is_grass_below_and_sky_above_and_moves_with_the_camera() {
    let gpu = strict_gpu();
    let scene = meadow_scene();
    let blades = field::generate(&scene.grass, scene.seed).unwrap();
    let (w, h) = (320, 180);
    let frame = render(&gpu, &scene, &blades, w, h, ViewMode::Shaded);

    // Most of the lower half is grass.
    let lower: Vec<_> = (h / 2..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .collect();
    let grass = lower
        .iter()
        .filter(|&&(x, y)| is_grass(pixel(&frame, x, y)))
        .count();
    let share = grass as f64 / lower.len() as f64;
    assert!(
        share > 0.75,
        "only {:.0}% of the lower half is grass-coloured",
        share * 100.0
    );

    // The top rows are sky: bright and blue-dominant.
    let [r, g, b] = mean_rgb(&frame, 0, 0, w, h / 8);
    assert!(
        b > g && g > r && b > 150.0,
        "top of the frame is not sky: {r:.0} {g:.0} {b:.0}"
    );

    // Another camera, another picture.
    let mut moved = scene.clone();
    moved.camera.position = [3.0, 2.5, 5.0];
    let other = render(&gpu, &moved, &blades, w, h, ViewMode::Shaded);
    let diff: f64 = frame
        .rgba
        .iter()
        .zip(&other.rgba)
        .map(|(a, b)| (*a as f64 - *b as f64).abs())
        .sum::<f64>()
        / frame.rgba.len() as f64;
    assert!(
        diff > 5.0,
        "moving the camera barely changed the picture (mean |diff| {diff:.2})"
    );
    finish(gpu);
}

/// A camera looking straight down (or straight up) has no world up to
/// orient by; it must still render what it looks at, not only sky.
#[test]
fn a_camera_looking_straight_down_sees_the_meadow() {
    let gpu = strict_gpu();
    let mut scene = meadow_scene();
    let blades = field::generate(&scene.grass, scene.seed).unwrap();
    scene.camera.position = [0.0, 6.0, 0.0];
    scene.camera.target = [0.0, 0.0, 0.0];
    let (w, h) = (160, 90);
    let frame = render(&gpu, &scene, &blades, w, h, ViewMode::Shaded);
    let grass = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| is_grass(pixel(&frame, x, y)))
        .count();
    let share = grass as f64 / (w * h) as f64;
    assert!(
        share > 0.5,
        "looking down on the meadow, only {:.0}% of the frame is grass",
        share * 100.0
    );
    finish(gpu);
}

/// The ground reaches the horizon: going up a column beside the grass,
/// from the soil at the bottom of the frame to the sky at the top, the
/// colour changes smoothly, with no band where the ground would end. A
/// ground drawn as a square (as it was) left a step from dark soil to pale
/// sky of over 100 levels at its edge, 6 m behind the bunches.
#[test]
fn the_ground_meets_the_sky_without_a_band() {
    let gpu = strict_gpu();
    let scene = Scene::builtin("fig10-few-bunches").unwrap();
    assert_eq!(scene.ground.half_extent, 6.0);
    let blades = field::generate(&scene.grass, scene.seed).unwrap();
    let (w, h) = (160, 90);
    let frame = render(&gpu, &scene, &blades, w, h, ViewMode::Shaded);
    finish(gpu);
    // Columns left and right of the three bunches.
    for x in [4, 12, w - 12, w - 5] {
        let column: Vec<[u8; 3]> = (0..h).rev().map(|y| pixel(&frame, x, y)).collect();
        let step = largest_step(&column);
        // Measured: at most 20 (the soil's own texture gives up to 14, the
        // haze into the horizon 20); the square's edge stepped from soil
        // (about 90, 76, 53) straight to sky (about 200, 218, 235).
        assert!(
            step <= 30,
            "column {x}: a step of {step} levels between rows: {column:?}"
        );
        // Soil (brown: red above blue) at the bottom, sky (blue) at the top.
        let [r, _, b] = column[0];
        assert!(r > b, "column {x} does not start on soil: {:?}", column[0]);
        let [r, _, b] = column[h as usize - 1];
        assert!(
            b > r,
            "column {x} does not end in sky: {:?}",
            column[h as usize - 1]
        );
    }
}

/// The sky follows the sun: under the shipped scenes' afternoon sun the
/// horizon is the day's pale blue all round; with the sun 3 degrees above
/// the horizon it glows warm (red over blue) toward the sun, less so away
/// from it, and the zenith is a deeper blue than the day's. The ground's
/// haze fades into that same horizon: no band where the ground ends.
#[test]
fn a_low_sun_warms_the_horizon_toward_it_and_the_ground_fades_into_it() {
    let gpu = strict_gpu();
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.light.shadow_map = 0;
    let blades = field::generate(&scene.grass, scene.seed).unwrap();
    let (w, h) = (160, 90);
    // Looking level along -z from 1.5 m: the horizon is the middle row.
    scene.camera.position = [0.0, 1.5, 0.0];
    scene.camera.target = [0.0, 1.5, -10.0];
    let horizon_and_zenith = |scene: &Scene| {
        let frame = render(&gpu, scene, &blades, w, h, ViewMode::Shaded);
        // Just above the horizon (the sky), and the top row.
        (
            pixel(&frame, w / 2, h / 2 - 3),
            pixel(&frame, w / 2, 0),
            frame,
        )
    };
    let warmth = |[r, _, b]: [u8; 3]| r as i32 - b as i32;
    let (day, day_top, _) = horizon_and_zenith(&scene);
    // The sun low ahead (toward -z), then low behind the camera.
    let low = 3f32.to_radians();
    scene.light.direction = [0.0, low.sin(), -low.cos()];
    let (ahead, ahead_top, frame) = horizon_and_zenith(&scene);
    scene.light.direction = [0.0, low.sin(), low.cos()];
    let (behind, _, _) = horizon_and_zenith(&scene);
    finish(gpu);
    assert!(warmth(day) < -30, "the day's horizon is blue: {day:?}");
    assert!(
        warmth(ahead) > 60,
        "toward a low sun the horizon glows: {ahead:?}"
    );
    assert!(
        warmth(behind) < warmth(ahead) - 40,
        "away from the sun less warm: {behind:?} against {ahead:?}"
    );
    let deeper = |[r, g, b]: [u8; 3]| r as u32 + g as u32 + b as u32;
    assert!(
        deeper(ahead_top) + 30 < deeper(day_top),
        "a low sun's zenith is darker: {ahead_top:?} against {day_top:?}"
    );
    // Down the frame's left column (away from the bunches): soil into the
    // warm horizon without a step, as in the day's frame.
    let column: Vec<[u8; 3]> = (0..h).rev().map(|y| pixel(&frame, 4, y)).collect();
    let step = largest_step(&column);
    assert!(
        step <= 30,
        "a step of {step} levels between rows: {column:?}"
    );
}

/// The largest change of any channel between neighbouring pixels of a
/// column: a band where the ground ends shows as a big one.
fn largest_step(column: &[[u8; 3]]) -> u32 {
    column
        .windows(2)
        .map(|p| {
            (0..3)
                .map(|c| p[0][c].abs_diff(p[1][c]) as u32)
                .max()
                .unwrap()
        })
        .max()
        .unwrap()
}

/// One straight blade rooted at `root`, leaning nowhere.
fn single_blade(root: Vec3, facing: Vec3, half_width: f32) -> Blade {
    Blade::from_profile(
        root,
        facing,
        [[0.0, 0.0], [0.0, 0.33], [0.0, 0.66], [0.0, 1.0]],
        half_width,
        BladeKind::Upright,
        0.5,
    )
}

#[test]
fn level_of_detail_gives_20_10_3_segments_by_distance_and_20_without_and_the_shadow_pass_its_own() {
    let gpu = strict_gpu();
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.camera.position = [0.0, 1.0, 0.0];
    scene.camera.target = [0.0, 0.5, -5.0];
    scene.lod.close_distance = 4.0;
    scene.lod.far_distance = 9.0;
    // One blade per frame: the distance thinning would drop the far one.
    scene.cull.thin_from = 0.0;
    // Root distances ~2.2 (close), ~6.1 (medium), ~15.0 (far); the shadow
    // pass's levels by the same distances to the camera.
    let cases = [(2.0, 20, 10), (6.0, 10, 5), (15.0, 3, 3)];
    assert_eq!(scene.lod.shadow_levels, [10, 5, 3]);
    // The distance levels alone (the texels' and the pixels' bounds are
    // the next tests').
    scene.lod.shadow_error_texels = 0.0;
    scene.lod.shadow_error_pixels = 0.0;
    for lod in [true, false] {
        scene.lod.enabled = lod;
        for (z, level, shadow_level) in cases {
            let blade = single_blade(Vec3::new(0.0, 0.0, -z), Vec3::Z, 0.02);
            let frame = render(&gpu, &scene, &[blade], 64, 64, ViewMode::Shaded);
            let stats = frame
                .statistics
                .expect("the device supports pipeline statistics");
            let expected = if lod { level } else { 20 };
            assert_eq!(stats.tessellation_control_patches, 1);
            // Isolines cut into N segments: N geometry-shader invocations,
            // each emitting one 4-vertex strip (2 triangles), the tip's
            // a 3-vertex one (1 triangle: its top closes to a point).
            assert_eq!(
                stats.geometry_shader_invocations, expected,
                "blade at {z} m, LOD {lod}"
            );
            assert_eq!(stats.geometry_shader_primitives, 2 * expected - 1);
            // At least the N + 1 distinct points of the curve are evaluated.
            assert!(stats.tessellation_evaluation_invocations > expected);
            // The shadow pass draws the blade (culling keeps it: its
            // shadow falls in view) at its own level, 20 without LOD.
            let shadow = frame.shadow_statistics.expect("shadows are on");
            let expected = if lod { shadow_level } else { 20 };
            assert_eq!(shadow.tessellation_control_patches, 1);
            assert_eq!(
                shadow.geometry_shader_invocations, expected,
                "shadow of the blade at {z} m, LOD {lod}"
            );
        }
    }
    finish(gpu);
}

/// The shadow-tessellation tests' scene: Fig. 10's, the camera 1 m up
/// looking down -z, the distance thinning off (one blade per frame).
fn shadow_caster_scene() -> Scene {
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.camera.position = [0.0, 1.0, 0.0];
    scene.camera.target = [0.0, 0.5, -5.0];
    scene.cull.thin_from = 0.0;
    scene
}

/// A bent blade rooted `distance` m down -z, with its control polygon's
/// total turn and reach (the inputs of blade.tesc's `shadow_segments`).
struct BentCaster {
    blade: Blade,
    turn: f32,
    reach: f32,
}

const CASTER_HALF_WIDTH: f32 = 0.01;

impl BentCaster {
    fn at(distance: f32) -> Self {
        let profile = [[0.0, 0.0], [0.05, 0.3], [0.2, 0.55], [0.4, 0.7]];
        let blade = Blade::from_profile(
            Vec3::new(0.0, 0.0, -distance),
            Vec3::X,
            profile,
            CASTER_HALF_WIDTH,
            BladeKind::Upright,
            0.5,
        );
        let p = blade.rest;
        let (d0, d1, d2) = (p[1] - p[0], p[2] - p[1], p[3] - p[2]);
        Self {
            blade,
            turn: d0.angle_between(d1) + d1.angle_between(d2),
            reach: d0.length() + d1.length() + d2.length(),
        }
    }

    /// `shadow_segments`' closed form within `tau` m, capped at the
    /// distance level 10: (segments, the chords' bound, the tip's).
    fn segments(&self, tau: f32) -> (u64, f32, f32) {
        let bend = (self.reach * self.turn / (8.0 * tau)).sqrt();
        let tip = (0.207 * CASTER_HALF_WIDTH / tau).powi(2);
        let one: f32 = if CASTER_HALF_WIDTH > 3.0 * tau {
            2.0
        } else {
            1.0
        };
        let segments = bend.max(tip).ceil().max(one).clamp(1.0, 10.0) as u64;
        (segments, bend, tip)
    }
}

/// A shadow-map texel's side (m) under the frame's light projection, in
/// a map of `map` texels.
fn shadow_texel(u: &meadow::render::FrameUniforms, map: u32) -> f32 {
    let row0 = glam::Mat4::from_cols_array_2d(&u.light_view_proj)
        .row(0)
        .truncate();
    2.0 / (row0.length() * map as f32)
}

/// The shadow pass tessellates a caster no finer than its size in the
/// map needs: a bent blade 2 m from the camera (shadow level 10 by
/// distance) casts with the segments the closed form of
/// glsl/blade/blade.tesc's `shadow_segments` gives for its control points
/// and the map's texel (its chords, its tapered tip within half a texel),
/// capped at 10: fewer in a coarse map, 10 in a fine one. (With the
/// chords' bound dropped from the shader by hand, the coarse maps' counts
/// fall below the closed form's and the test fails.)
#[test]
fn the_shadow_pass_tessellates_a_caster_by_its_size_in_the_map() {
    let gpu = strict_gpu();
    let mut scene = shadow_caster_scene();
    assert_eq!(scene.lod.shadow_error_texels, 0.5);
    // The map's bound alone (the view's is the next test's).
    scene.lod.shadow_error_pixels = 0.0;
    let caster = BentCaster::at(2.0);
    let mut counts = Vec::new();
    for map in [256, 1024, 4096, 16384] {
        scene.set_shadow_map(map).unwrap();
        let u = meadow::render::FrameUniforms::new(&scene, 64, 64, ViewMode::Shaded, 0.0);
        let texel = shadow_texel(&u, map);
        let (expected, bend, tip) = caster.segments(0.5 * texel);
        let frame = render(&gpu, &scene, &[caster.blade], 64, 64, ViewMode::Shaded);
        let shadow = frame.shadow_statistics.expect("shadows are on");
        eprintln!(
            "map {map}: texel {:.2} mm, bend {bend:.2}, tip {tip:.2}: {} segments",
            texel * 1e3,
            shadow.geometry_shader_invocations
        );
        assert_eq!(shadow.geometry_shader_invocations, expected, "map {map}");
        counts.push(expected);
    }
    assert!(counts.is_sorted(), "{counts:?}");
    assert!(counts[0] < 10 && counts[3] == 10, "{counts:?}");
    finish(gpu);
}

/// How far the sun carries a unit departure of a caster's shape across
/// the rays of the view on flat ground, at most: the largest singular
/// value of the map that drops a departure d down the sun's rays to the
/// ground, d - (d.y / l.y) l, and shows the ground's horizontal move g as
/// (g . across, rise g . along) of a ray `ray`, `along` its horizontal
/// direction (blade.tesc's `ground_stretch`).
fn ground_stretch(light: Vec3, ray: Vec3, rise: f32) -> f32 {
    let along = Vec3::new(ray.x, 0.0, ray.z).normalize();
    let across = Vec3::Y.cross(along);
    let drop =
        glam::Mat3::IDENTITY - glam::Mat3::from_cols(light * 0.0, light / light.y, light * 0.0);
    let (a1, a2) = (drop.transpose() * across, rise * (drop.transpose() * along));
    let (a, b, c) = (a1.dot(a1), a1.dot(a2), a2.dot(a2));
    (0.5 * (a + c) + (0.25 * (a - c) * (a - c) + b * b).sqrt()).sqrt()
}

/// glsl/blade/blade.tesc's `shadow_tolerance` for `caster` in `scene`
/// drawn `side` x `side` with a map of `map` texels, mirrored from the
/// frame's camera and sun: `lod.shadow_error_pixels` of the view's pixels
/// at the caster's nearest visible receiver, or half a texel where more.
fn view_tolerance(scene: &Scene, caster: &BentCaster, side: u32, map: u32) -> (f32, f32) {
    let u = meadow::render::FrameUniforms::new(scene, side, side, ViewMode::Shaded, 0.0);
    let fov = scene.camera.fov_y.to_radians();
    let pixel_per_depth = 2.0 * (fov / 2.0).tan() / side as f32;
    assert!((u.pixel_per_depth_m - pixel_per_depth).abs() < 1e-6 * pixel_per_depth);
    let eye = Vec3::from(scene.camera.position);
    let forward = (Vec3::from(scene.camera.target) - eye).normalize();
    let light = Vec3::from(scene.light.direction).normalize();
    let texel = shadow_texel(&u, map);
    // The shadow filter's reach past the shadow's volume.
    let blur = texel * (meadow::render::shadow_params::ShadowParams::of(map).pcf_radius + 2.0);
    let top = caster.reach + blur;
    // Its shadow falls from the blade (within its reach of the root)
    // down the sun's rays to the ground (flat: the lowest is 0), nearer
    // the eye only where the sun is ahead of it.
    let ahead = light.dot(forward).max(0.0);
    let ray = caster.blade.rest[0] - eye;
    let depth = ray.dot(forward);
    let nearest = depth - caster.reach - blur - ahead * top / light.y;
    // A receiver no higher than the blade's top is seen only where the
    // view's lowest rays (no roll: its bottom edge, tan(fov / 2) below
    // the axis) have fallen from the eye to it.
    let slope = forward.y - (fov / 2.0).tan() * glam::Vec2::new(forward.x, forward.z).length();
    assert!(
        (u.view_bottom_slope - slope).abs() < 1e-4,
        "{} {slope}",
        u.view_bottom_slope
    );
    let seen_from = (eye.y - top).max(0.0) / -slope;
    let receiver_depth = nearest.max(seen_from);
    let off_axis = depth / ray.length();
    // The ray to a receiver rises at most from the ground to the eye.
    let rise = (eye.y / receiver_depth).min(1.0);
    let tau_pixels = scene.lod.shadow_error_pixels * receiver_depth * pixel_per_depth * off_axis
        / ground_stretch(light, ray, rise);
    let tau_texels = 0.5 * texel;
    (tau_pixels.max(tau_texels), tau_texels)
}

/// ... and no finer than the view shows its shadow: in a fine map
/// (16384 texels), a bent blade casts with the segments that keep its
/// shape within `lod.shadow_error_pixels` (one) pixels of the view at its
/// nearest visible receiver (`view_tolerance`, the shader's mirror):
/// fewer in a small image, the distance level (10) in a large one; 3 m
/// away with the sun behind the eye (its shadow falls away from it), 3 m
/// away with the sun ahead (its shadow falls toward it), and 1 m away,
/// where the view shows no receiver nearer than where its lowest rays
/// meet the blade's top. (With the pixel's size taken at the caster
/// instead of its nearest receiver, the small images' counts fall below
/// the closed form's and the test fails; with the view's lowest rays left
/// out, the near caster's counts rise above it.)
#[test]
fn the_shadow_pass_tessellates_a_caster_by_what_the_view_shows_of_it() {
    let gpu = strict_gpu();
    let mut scene = shadow_caster_scene();
    scene.set_shadow_map(16384).unwrap();
    assert_eq!(scene.lod.shadow_error_pixels, 1.0);
    let behind = scene.light.direction;
    let cases = [
        (
            "3 m, the sun behind",
            3.0,
            behind,
            &[32, 64, 128, 256, 1024][..],
        ),
        (
            "3 m, the sun ahead",
            3.0,
            [0.3, 0.7, -0.6],
            &[32, 64, 128, 256, 1024][..],
        ),
        ("1 m, the sun behind", 1.0, behind, &[32, 64, 256][..]),
    ];
    for (what, distance, light, sides) in cases {
        scene.light.direction = light;
        let caster = BentCaster::at(distance);
        let mut counts = Vec::new();
        for &side in sides {
            let (tau, tau_texels) = view_tolerance(&scene, &caster, side, 16384);
            let (expected, bend, _) = caster.segments(tau);
            let frame = render(&gpu, &scene, &[caster.blade], side, side, ViewMode::Shaded);
            let shadow = frame.shadow_statistics.expect("shadows are on");
            eprintln!(
                "{what}, {side} px: tolerance {:.2} mm (texels' {:.2}), bend {bend:.2}: {} segments",
                tau * 1e3,
                tau_texels * 1e3,
                shadow.geometry_shader_invocations
            );
            assert_eq!(
                shadow.geometry_shader_invocations, expected,
                "{what}, {side} px"
            );
            counts.push(expected);
        }
        assert!(counts.is_sorted(), "{what}: {counts:?}");
        assert!(counts[0] < counts[sides.len() - 1], "{what}: {counts:?}");
    }
    finish(gpu);
}

/// The linear value of an sRGB-encoded channel mean (0..255).
fn linear(c: f64) -> f64 {
    let c = c / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[test]
fn lighting_is_two_sided() {
    let gpu = strict_gpu();
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.camera.position = [0.0, 0.5, 2.0];
    scene.camera.target = [0.0, 0.5, 0.0];
    scene.camera.fov_y = 30.0;
    scene.light.ambient = 0.05;
    // The diffuse light alone: no sheen, no canopy's shade.
    scene.grass.look.sheen = 0.0;
    scene.grass.look.self_shadowing = false;
    let brightness = |facing: Vec3, light: [f32; 3]| {
        let mut s = scene.clone();
        s.light.direction = light;
        let blade = single_blade(Vec3::ZERO, facing, 0.15);
        let frame = render(&gpu, &s, &[blade], 128, 128, ViewMode::Shaded);
        mean_rgb(&frame, 56, 56, 72, 72).map(linear)
    };
    let toward_camera = [0.0, 0.0, 1.0];
    // The face seen by the camera is the front face in one case and the
    // back face in the other: both must be lit from the camera's side.
    let front = brightness(Vec3::Z, toward_camera);
    let back = brightness(-Vec3::Z, toward_camera);
    // Lit from behind, the visible side gets the light through the blade:
    // a leaf's transmittance, 0.85 of its reflectance, greener and
    // yellower (tinted 1.05, 1, 0.45: docs/method.md section 4b). With the
    // ambient sky (0.05 x 0.75 on an upright blade) the seen light over
    // the lit side's is (0.0375 + 0.85 c t) / (0.0375 + c), c the sun's
    // colour and t the tint, per channel.
    let behind = brightness(Vec3::Z, [0.0, 0.0, -1.0]);
    assert!(
        (front[1] - back[1]).abs() < 0.1 * front[1],
        "front {front:?} vs back {back:?}"
    );
    let color = scene.light.color.map(f64::from);
    for (c, tint) in [(1, 1.0), (2, 0.45)] {
        let expected = (0.0375 + 0.85 * color[c] * tint) / (0.0375 + color[c]);
        let ratio = behind[c] / front[c];
        assert!(
            (ratio - expected).abs() < 0.06 * expected,
            "channel {c}: back-lit over lit {ratio:.3}, a leaf's {expected:.3}"
        );
    }
    finish(gpu);
}

#[test]
fn lod_view_colors_blades_by_level() {
    let gpu = strict_gpu();
    let mut scene = meadow_scene();
    scene.grass.meadow = vec![Meadow {
        center: [0.0, 0.0],
        size: [8.0, 24.0],
        count: Some(20_000),
        density: None,
        mask: None,
        mask_map: None,
    }];
    let blades = field::generate(&scene.grass, 5).unwrap();
    let frame = render(&gpu, &scene, &blades, 320, 180, ViewMode::Lod);
    let count = |pred: fn([u8; 3]) -> bool| {
        (0..frame.height)
            .flat_map(|y| (0..frame.width).map(move |x| (x, y)))
            .filter(|&(x, y)| pred(pixel(&frame, x, y)))
            .count()
    };
    let red = count(|[r, g, b]| r > 120 && g < 60 && b < 60);
    let yellow = count(|[r, g, b]| r > 120 && g > 100 && b < 60);
    let blue = count(|[r, g, b]| b > 120 && r < 60 && g < 120);
    assert!(
        red > 500 && yellow > 500 && blue > 200,
        "red {red}, yellow {yellow}, blue {blue}"
    );
    finish(gpu);
}

/// Mean x of the grass pixels (green: the sky and the soil are not) in the
/// top 40 % of the picture, where the tips are, and how many there are.
fn grass_centroid(path: &std::path::Path) -> (f64, usize) {
    let img = image::open(path).unwrap().to_rgb8();
    let (mut sum, mut n) = (0.0, 0usize);
    for (x, y, p) in img.enumerate_pixels() {
        if y < img.height() * 2 / 5 && is_grass(p.0) {
            sum += x as f64;
            n += 1;
        }
    }
    (sum / n.max(1) as f64, n)
}

#[test]
fn the_wind_from_the_left_sways_the_grass_to_the_right_over_frames() {
    use meadow::commands::render::render_to_dir;
    let request = common::strict_request(
        Scene::builtin("fig10-few-bunches").unwrap(),
        320,
        180,
        3,
        1.0,
    );
    let dir = std::env::temp_dir().join(format!("meadow-sway-{}", std::process::id()));
    let report = render_to_dir(&request, &dir).expect("animation");
    assert_eq!(report.validation.errors, 0);
    assert_eq!(report.frames.len(), 3);
    assert_eq!(report.sim_steps, 120, "2 s of 1/60 s steps");
    let rest = grass_centroid(&dir.join("frame_0000.png"));
    let later = [1, 2].map(|f| grass_centroid(&dir.join(format!("frame_{f:04}.png"))));
    eprintln!(
        "grass centroid x (pixels, count): rest {rest:?}, 1 s {:?}, 2 s {:?}",
        later[0], later[1]
    );
    assert!(rest.1 > 100, "too few tips in view: {rest:?}");
    for (x, n) in later {
        // Measured on lavapipe: +6.2 px after 1 s, +8.5 px after 2 s.
        assert!(
            x > rest.0 + 3.0,
            "the tips did not lean downwind: {x} vs {}",
            rest.0
        );
        assert!(n > 100);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn motion_view_is_blue_at_rest_and_warms_as_the_wind_bends_the_blades() {
    use meadow::commands::render::{render_to_dir, Animation, RenderRequest};
    use meadow::gpu::{GpuOptions, ValidationOptions};
    std::env::set_var("MEADOW_QUIET_VALIDATION", "1");
    let dir = std::env::temp_dir().join(format!("meadow-motion-{}", std::process::id()));
    let mut request = RenderRequest {
        scene: Scene::builtin("fig10-few-bunches").unwrap(),
        width: 240,
        height: 135,
        msaa: 1,
        view: ViewMode::Motion,
        animation: Animation::default(),
        every: 1,
        gif: false,
        video: None,
        overwrite: false,
        light_waves: false,
        gpu: GpuOptions {
            validation: ValidationOptions::strict(),
            ..Default::default()
        },
    };
    // Red minus blue over the pixels that are blades (not sky, not soil:
    // the motion view paints blades from blue, at rest, to red, bent 0.6 rad).
    let warmth = |path: std::path::PathBuf| {
        let img = image::open(path).unwrap().to_rgb8();
        let blades: Vec<[i32; 3]> = img
            .pixels()
            .map(|p| p.0.map(i32::from))
            // Blade colours stand 40+ above green in red or blue; the sky
            // (188, 209, 233) and the soil (95, 80, 53) do not.
            .filter(|[r, g, b]| b - g > 40 || r - g > 40)
            .collect();
        let n = blades.len().max(1) as f64;
        (
            blades.iter().map(|[r, _, b]| (r - b) as f64).sum::<f64>() / n,
            blades.len(),
        )
    };
    render_to_dir(&request, &dir.join("rest")).expect("rest");
    request.animation.start = 2.0;
    render_to_dir(&request, &dir.join("wind")).expect("2 s of wind");
    let rest = warmth(dir.join("rest/frame_0000.png"));
    let wind = warmth(dir.join("wind/frame_0000.png"));
    eprintln!(
        "motion view red - blue over blade pixels (mean, count): rest {rest:?}, after 2 s {wind:?}"
    );
    assert!(rest.1 > 200 && wind.1 > 200);
    assert!(rest.0 < -50.0, "blades at rest are not blue: {rest:?}");
    assert!(
        wind.0 > rest.0 + 40.0,
        "bent blades did not warm: {rest:?} -> {wind:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Fig. 10's scene seen from above, the sun low in the +x direction (45
/// degrees up), a 2048 shadow map: shadows fall along -x.
fn seen_from_above_with_the_sun_at_45_degrees() -> Scene {
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.camera.position = [0.0, 3.0, 0.6];
    scene.camera.target = [0.0, 0.0, 0.0];
    scene.light.direction = [1.0, 1.0, 0.0];
    scene.light.shadow_map = 2048;
    scene
}

#[test]
fn a_tall_blade_shadows_the_ground_on_the_side_away_from_the_light() {
    let gpu = strict_gpu();
    let scene = seen_from_above_with_the_sun_at_45_degrees();
    // One wide 1 m blade at the origin, its face to the sun (width along z).
    let blades = [single_blade(Vec3::ZERO, Vec3::X, 0.03)];
    let (w, h) = (320, 320);
    let lit = render(&gpu, &scene, &blades, w, h, ViewMode::Shaded);
    let mut unshadowed = scene.clone();
    unshadowed.light.shadow_map = 0;
    let plain = render(&gpu, &unshadowed, &blades, w, h, ViewMode::Shaded);

    // Darkened pixels: where the shadow pass takes light away.
    let (root_x, _) = project(&scene, Vec3::ZERO, w, h);
    let (tip_shadow_x, _) = project(&scene, Vec3::new(-1.0, 0.0, 0.0), w, h);
    let mut left = 0;
    let mut right = 0;
    for y in 0..h {
        for x in 0..w {
            let a = pixel(&lit, x, y).iter().map(|&c| c as i32).sum::<i32>();
            let b = pixel(&plain, x, y).iter().map(|&c| c as i32).sum::<i32>();
            if b - a > 30 {
                if (x as f32) < root_x - 3.0 {
                    left += 1;
                } else if (x as f32) > root_x + 3.0 {
                    right += 1;
                }
            }
        }
    }
    // A blade 1 m tall under a 45-degree sun casts a shadow 1 m long: on
    // the -x side, reaching about to where x = -1 lands.
    assert!(
        left > 100,
        "too few shadowed pixels on the far side: {left} (light side {right})"
    );
    assert!(
        right * 50 < left,
        "shadow on the light's side: {right} vs {left}"
    );
    let far_end = (0..w)
        .filter(|&x| {
            (0..h).any(|y| {
                let a = pixel(&lit, x, y).iter().map(|&c| c as i32).sum::<i32>();
                let b = pixel(&plain, x, y).iter().map(|&c| c as i32).sum::<i32>();
                b - a > 30
            })
        })
        .min()
        .unwrap() as f32;
    assert!(
        (far_end - tip_shadow_x).abs() < 0.1 * (root_x - tip_shadow_x),
        "shadow ends at x = {far_end}, the tip's shadow should be near {tip_shadow_x}"
    );
    finish(gpu);
}

/// A caster's shadow keeps its area however few segments the shadow pass
/// gives it: a wide straight blade under a 45-degree sun darkens as much
/// ground cut into one segment as into 20 (glsl/blade/blade.tesc's
/// `taper_area_gain`). Without the gain, one segment's triangle casts a
/// quarter less than the tapered blade (1/2 of its root's width times its
/// length against 2/3), and the test fails.
#[test]
fn a_caster_cut_into_fewer_segments_casts_as_much_shadow() {
    let gpu = strict_gpu();
    let mut scene = seen_from_above_with_the_sun_at_45_degrees();
    scene.lod.enabled = true;
    scene.lod.shadow_error_texels = 0.0;
    scene.lod.shadow_error_pixels = 0.0;
    let blades = [single_blade(Vec3::ZERO, Vec3::X, 0.06)];
    let (w, h) = (320, 320);
    let mut unshadowed = scene.clone();
    unshadowed.light.shadow_map = 0;
    let plain = render(&gpu, &unshadowed, &blades, w, h, ViewMode::Shaded);
    let (root_x, _) = project(&scene, Vec3::ZERO, w, h);
    let shadowed = |segments: u32| {
        let mut s = scene.clone();
        s.lod.shadow_levels = [segments; 3];
        let lit = render(&gpu, &s, &blades, w, h, ViewMode::Shaded);
        assert_eq!(
            lit.shadow_statistics
                .expect("shadows are on")
                .geometry_shader_invocations,
            u64::from(segments)
        );
        // The ground beyond the blade's own footprint.
        (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let a = pixel(&lit, x, y).iter().map(|&c| c as i32).sum::<i32>();
                let b = pixel(&plain, x, y).iter().map(|&c| c as i32).sum::<i32>();
                b - a > 30 && (x as f32) < root_x - 3.0
            })
            .count() as f64
    };
    let fine = shadowed(20);
    let coarse = shadowed(1);
    let three = shadowed(3);
    eprintln!("shadowed pixels: 20 segments {fine}, 3 segments {three}, 1 segment {coarse}");
    assert!(
        fine > 1000.0,
        "too small a shadow to measure: {fine} pixels"
    );
    for (n, count) in [(1, coarse), (3, three)] {
        assert!(
            (count / fine - 1.0).abs() < 0.06,
            "{n} segment(s) shadow {count} pixels against 20's {fine}"
        );
    }
    finish(gpu);
}

/// Obstacles are drawn where the wind sees them (paper Fig. 13 shows what
/// blocks the wind): a post stands where its cylinder is, in its own
/// colour, lit on the sun's side, and casts a shadow as long as a 45-degree
/// sun makes it, on the side away from the light.
#[test]
fn an_obstacle_is_drawn_where_it_stands_and_casts_its_shadow() {
    use meadow::model::wind::Obstacle;
    let gpu = strict_gpu();
    let mut scene = seen_from_above_with_the_sun_at_45_degrees();
    // One blade far off, so the frame has grass to draw.
    let blades = [single_blade(Vec3::new(0.0, 0.0, -1.2), Vec3::X, 0.01)];
    let (w, h) = (320, 320);
    let bare = render(&gpu, &scene, &blades, w, h, ViewMode::Shaded);
    scene.wind.obstacles = vec![Obstacle::Cylinder {
        base: Vec3::ZERO,
        radius: 0.08,
        height: 1.0,
    }];
    let with_post = render(&gpu, &scene, &blades, w, h, ViewMode::Shaded);
    finish(gpu);
    let brightness = |f: &meadow::frame::Frame, p: Vec3| {
        let (x, y) = project(&scene, p, w, h);
        pixel(f, x as u32, y as u32)
            .iter()
            .map(|&c| c as i32)
            .sum::<i32>()
    };
    // The post's top, seen from above: wood (red over green over blue),
    // where bare soil was before.
    let (x, y) = project(&scene, Vec3::new(0.0, 1.0, 0.0), w, h);
    let top = pixel(&with_post, x as u32, y as u32);
    assert!(
        top[0] > top[1] && top[1] > top[2] && top != pixel(&bare, x as u32, y as u32),
        "no post drawn at its top: {top:?}"
    );
    // Its shadow: a 1 m post under a 45-degree sun from +x darkens the
    // ground from its foot to 1 m on the -x side, and nothing on +x.
    for d in [0.3, 0.6, 0.85] {
        let p = Vec3::new(-d, 0.0, 0.0);
        let (lit, shadowed) = (brightness(&bare, p), brightness(&with_post, p));
        assert!(
            shadowed < lit * 3 / 4,
            "ground {d} m behind the post not in its shadow: {lit} -> {shadowed}"
        );
        let q = Vec3::new(d, 0.0, 0.0);
        assert!(
            (brightness(&bare, q) - brightness(&with_post, q)).abs() < 10,
            "the sun's side of the post darkened at {d} m"
        );
    }
    let beyond = Vec3::new(-1.25, 0.0, 0.0);
    assert!(
        (brightness(&bare, beyond) - brightness(&with_post, beyond)).abs() < 10,
        "the shadow reaches past the post's height"
    );
}

/// A binding past the device's maxStorageBufferRange is refused before
/// the driver sees it, with one line naming the limit and what to make
/// smaller; the objects made before it are released (validation clean,
/// nothing leaked). With a 64 KiB limit table1's wind grid is too big.
#[test]
fn a_binding_past_the_storage_range_is_one_clear_error() {
    let gpu = common::strict_gpu_with(Some(1 << 16));
    let mut scene = meadow_scene();
    scene.set_blade_count(1000).unwrap();
    let blades = scene.field().unwrap();
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed).unwrap();
    let error =
        meadow::frame::FrameRecorder::new(&gpu, &scene, (64, 36), 1, &blades, Some(&dynamic))
            .err()
            .expect("table1's wind grid is over 64 KiB")
            .to_string();
    assert!(
        error.contains("maxStorageBufferRange of 65536")
            && error.contains("fewer wind cells or blades")
            && !error.contains('\n'),
        "{error}"
    );
    finish(gpu);
}

/// report.json's `device_memory`: ten times the blades take at least
/// their records more (each blade's physics record and its four control
/// points), and not absurdly more.
#[test]
fn report_json_counts_the_device_memory_the_blades_hold() {
    use meadow::commands::render::render_to_dir;
    use meadow::interface::{BladeVertex, GrassBlade};
    let dir = std::env::temp_dir().join(format!("meadow-memory-{}", std::process::id()));
    let peak = |blades: usize| {
        let mut scene = Scene::builtin("table1").unwrap();
        scene.set_blade_count(blades).unwrap();
        let request = common::strict_request(scene, 160, 90, 1, 1.0);
        let out = dir.join(blades.to_string());
        let report = render_to_dir(&request, &out).expect("render");
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap())
                .unwrap();
        let memory = &json["device_memory"];
        let allocated = memory["allocated_bytes"].as_u64().expect("allocated_bytes");
        let peak = memory["peak_bytes"].as_u64().expect("peak_bytes");
        assert_eq!(peak, report.device_memory.peak_bytes);
        assert!(0 < allocated && allocated <= peak, "{memory}");
        peak
    };
    let (small, large) = (peak(2_000), peak(20_000));
    let per_blade = (large - small) as f64 / 18_000.0;
    let records = std::mem::size_of::<GrassBlade>() + 4 * std::mem::size_of::<BladeVertex>();
    eprintln!("peak {small} B at 2,000 blades, {large} B at 20,000: {per_blade:.0} B a blade (records {records} B)");
    assert!(per_blade >= records as f64, "{per_blade:.0} B a blade");
    assert!(per_blade < 8192.0, "{per_blade:.0} B a blade");
    let _ = std::fs::remove_dir_all(&dir);
}
