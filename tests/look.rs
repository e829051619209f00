//! How the grass looks (docs/method.md, "A blade's light" and "Light in
//! the canopy"): the cuticle's sheen against its closed form, the canopy's
//! shade of its own floor against Beer-Lambert's, the ground under grass
//! (the sward's floor, not soil), and the waves of light a gust sends over
//! a dense meadow, measured as `meadow render --light-waves` measures them.
//! Every render runs under strict validation.

use crate::common;

use common::{finish, render, strict_gpu};
use glam::Vec3;
use meadow::commands::render::render_to_dir;
use meadow::model::{Blade, BladeKind};
use meadow::render::ViewMode;
use meadow::scene::{Bunch, Cover, Meadow, Scene};

/// The linear value of an sRGB-encoded byte.
fn linear(c: u8) -> f64 {
    let c = c as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The linear green channel's mean over a rectangle of a frame.
fn mean_linear(frame: &meadow::frame::Frame, x0: u32, y0: u32, x1: u32, y1: u32, c: usize) -> f64 {
    let mut sum = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            sum += linear(frame.rgba[((y * frame.width + x) * 4) as usize + c]);
        }
    }
    sum / ((x1 - x0) * (y1 - y0)) as f64
}

/// One straight upright blade at `root` facing `facing`.
fn upright_blade(root: Vec3, facing: Vec3, height: f32, half_width: f32) -> Blade {
    Blade::from_profile(
        root,
        facing,
        [
            [0.0, 0.0],
            [0.0, 0.33 * height],
            [0.0, 0.66 * height],
            [0.0, height],
        ],
        half_width,
        BladeKind::Upright,
        0.5,
    )
}

/// A scene whose grass is one bunch of one blade at the origin (the tests
/// render blades of their own in it; its patch places the clear ground).
fn lone_blade_scene() -> Scene {
    let mut scene = Scene::builtin("fig10-few-bunches").unwrap();
    scene.grass.bunch = vec![Bunch {
        center: [0.0, 0.0],
        radius: 0.05,
        count: 1,
    }];
    scene.grass.meadow.clear();
    scene
}

// The cuticle's sheen as glsl/common/leaf_optics.glsl writes it, here in
// closed form: GGX, Smith's height-correlated visibility, Schlick's
// Fresnel with the wax's F0.
const CUTICLE_F0: f64 = 0.04;
const CUTICLE_ALPHA: f64 = 0.28;

fn sheen_closed_form(n: glam::DVec3, v: glam::DVec3, l: glam::DVec3) -> f64 {
    let h = (l + v).normalize();
    let (n_l, n_v, n_h, v_h) = (n.dot(l), n.dot(v), n.dot(h), v.dot(h));
    let a2 = CUTICLE_ALPHA * CUTICLE_ALPHA;
    let d = a2 / (std::f64::consts::PI * (n_h * n_h * (a2 - 1.0) + 1.0).powi(2));
    let vis = 0.5
        / (n_l * (n_v * n_v * (1.0 - a2) + a2).sqrt() + n_v * (n_l * n_l * (1.0 - a2) + a2).sqrt());
    let f = CUTICLE_F0 + (1.0 - CUTICLE_F0) * (1.0 - v_h).powi(5);
    std::f64::consts::PI * d * vis * f * n_l
}

/// A blade turned to face the half vector between the sun and the eye
/// shines: the light the sheen adds at its midrib (sheen 1 against sheen
/// 0, the same frame otherwise) is the closed form's, the sun's colour
/// times GGX's highlight. With the sheen switched off by hand in the
/// shader the two frames are the same and this fails.
#[test]
fn the_sheen_at_a_blade_facing_the_half_vector_is_the_closed_form() {
    let gpu = strict_gpu();
    let mut scene = lone_blade_scene();
    // The blade's own texture, lit without shadows or the canopy's shade:
    // only the sheen differs between the two frames.
    scene.light.shadow_map = 0;
    scene.grass.look.self_shadowing = false;
    scene.camera.position = [0.0, 0.75, 2.0];
    scene.camera.target = [0.0, 0.5, 0.0];
    scene.camera.fov_y = 30.0;
    // The eye is along +z (and a little up) from the blade's middle; the
    // sun 70 degrees round from it, 12 degrees up: the half vector lies
    // between them, and the blade faces it.
    let middle = glam::DVec3::new(0.0, 0.5, 0.0);
    let v = (glam::DVec3::new(0.0, 0.75, 2.0) - middle).normalize();
    let sun_azimuth = 70f64.to_radians();
    let l = glam::DVec3::new(
        sun_azimuth.sin() * 12f64.to_radians().cos(),
        12f64.to_radians().sin(),
        sun_azimuth.cos() * 12f64.to_radians().cos(),
    );
    scene.light.direction = [l.x as f32, l.y as f32, l.z as f32];
    let h = (l + v).normalize();
    let facing = Vec3::new(h.x as f32, 0.0, h.z as f32).normalize();
    let blade = upright_blade(Vec3::ZERO, facing, 1.0, 0.15);
    let (w, hgt) = (128, 128);
    let mut frames = Vec::new();
    for sheen in [1.0, 0.0] {
        scene.grass.look.sheen = sheen;
        frames.push(render(&gpu, &scene, &[blade], w, hgt, ViewMode::Shaded));
    }
    // The blade's middle (0.5 m up) at the frame's centre: a few pixels
    // about it, on the midrib where the normal is the blade's own.
    let (x, y) = common::project(&scene, Vec3::new(0.0, 0.5, 0.0), w, hgt);
    let (x, y) = (x.round() as u32, y.round() as u32);
    let n = glam::DVec3::new(facing.x as f64, 0.0, facing.z as f64);
    // The face toward the eye: the shader flips the normal on back faces.
    let n = if n.dot(v) < 0.0 { -n } else { n };
    let expected = sheen_closed_form(n, v, l) * scene.light.color[1] as f64;
    let with = mean_linear(&frames[0], x - 1, y - 2, x + 2, y + 3, 1);
    let without = mean_linear(&frames[1], x - 1, y - 2, x + 2, y + 3, 1);
    let added = with - without;
    eprintln!("sheen at the midrib: {added:.4} (closed form {expected:.4}), diffuse {without:.4}");
    assert!(
        expected > 0.05,
        "the geometry puts the blade at the highlight: {expected}"
    );
    assert!(
        (added - expected).abs() < 0.15 * expected,
        "the sheen adds {added:.4}, the closed form {expected:.4}"
    );
    finish(gpu);
}

/// Far over the clear ground the grass takes the haze the ground takes
/// (glsl/common/haze.glsl): a blade 40 m from the grass, its clear ground
/// 5 m, is the colour of the hazed ground beside it, not a green blade
/// standing over fog; with 200 m of clear ground it is green.
#[test]
fn far_over_the_clear_ground_the_grass_fades_into_the_haze_as_the_ground_does() {
    let gpu = strict_gpu();
    let mut scene = lone_blade_scene();
    scene.light.shadow_map = 0;
    scene.camera.position = [0.0, 1.0, -36.0];
    scene.camera.target = [0.0, 0.5, -40.0];
    scene.camera.fov_y = 30.0;
    let blade = upright_blade(Vec3::new(0.0, 0.0, -40.0), Vec3::Z, 1.0, 0.2);
    let (w, h) = (96, 96);
    let (x, y) = common::project(&scene, Vec3::new(0.0, 0.5, -40.0), w, h);
    let (x, y) = (x.round() as u32, y.round() as u32);
    let gap = |frame: &meadow::frame::Frame| {
        (0..3)
            .map(|c| {
                let blade = mean_linear(frame, x - 1, y - 1, x + 2, y + 2, c);
                let ground = mean_linear(frame, 4, y - 1, 8, y + 2, c);
                (blade - ground).abs()
            })
            .fold(0.0, f64::max)
    };
    let mut gaps = Vec::new();
    for clear in [5.0, 200.0] {
        scene.ground.half_extent = clear;
        gaps.push(gap(&render(&gpu, &scene, &[blade], w, h, ViewMode::Shaded)));
    }
    eprintln!(
        "blade against the ground beside it: {:.4} with 5 m of clear ground, {:.4} with 200 m",
        gaps[0], gaps[1]
    );
    assert!(
        gaps[1] > 0.05,
        "the clear blade is not apart from the ground: {}",
        gaps[1]
    );
    assert!(
        gaps[0] < 0.2 * gaps[1],
        "the hazed blade stands out: {}",
        gaps[0]
    );
    finish(gpu);
}

// Light in the canopy as glsl/common/canopy.glsl writes it.
fn leaf_projection(cos_theta: f64, cos_theta_l: f64) -> f64 {
    let (c, cl) = (cos_theta.clamp(0.0, 1.0), cos_theta_l.clamp(0.0, 1.0));
    let (s, sl) = ((1.0 - c * c).sqrt(), (1.0 - cl * cl).sqrt());
    let k = c * cl / (s * sl).max(1e-6);
    if k >= 1.0 {
        return c * cl;
    }
    let phi = k.acos();
    c * cl * (1.0 - 2.0 * phi / std::f64::consts::PI)
        + 2.0 / std::f64::consts::PI * s * sl * (1.0 - k * k).sqrt()
}

/// Ross's G against its known cases: flat leaves project their whole
/// area toward the zenith and cos(theta) elsewhere, upright ones
/// (2/pi) sin(theta), and leaves at every angle in equal measure
/// (spherical) about 0.5 from every direction.
#[test]
fn the_leaf_projection_has_ross_s_known_values() {
    for theta in [0.0f64, 0.3, 0.8, 1.2, 1.5] {
        let c = theta.cos();
        assert!((leaf_projection(c, 1.0) - c).abs() < 1e-9);
        assert!((leaf_projection(c, 0.0) - 2.0 / std::f64::consts::PI * theta.sin()).abs() < 1e-6);
        // The spherical distribution: leaf normals' inclinations weighted
        // by sin(theta_l); its G is 0.5 from every direction.
        let steps = 2000;
        let g: f64 = (0..steps)
            .map(|i| {
                let tl = (i as f64 + 0.5) / steps as f64 * std::f64::consts::FRAC_PI_2;
                leaf_projection(c, tl.cos()) * tl.sin() * std::f64::consts::FRAC_PI_2 / steps as f64
            })
            .sum();
        assert!((g - 0.5).abs() < 2e-3, "theta {theta}: G {g}");
    }
}

/// The floor of a dense meadow, seen from above with its blades left out:
/// with self-shadowing the sky's and the sun's light reach it through the
/// canopy by Beer-Lambert's law (leaf area index from the density and the
/// blades' mean area), so its light over the floor's without is the
/// closed form's. Outside the meadow the ground is soil, lit as before.
/// With self-shadowing switched off by hand the floor is as bright as
/// without it, and this fails; with the floor's grass colour switched
/// off, so does the colour check.
#[test]
fn the_canopy_shades_its_floor_by_beer_lambert_and_the_floor_is_grass_not_soil() {
    let gpu = strict_gpu();
    let mut scene = Scene::builtin("table1").unwrap();
    scene.light.shadow_map = 0;
    scene.light.direction = [0.3, 0.8, 0.2];
    scene.grass.meadow = vec![Meadow {
        center: [0.0, 0.0],
        size: [4.0, 4.0],
        count: None,
        density: Some(300.0),
        mask: None,
        mask_map: None,
    }];
    scene.camera.position = [0.0, 6.0, 0.01];
    scene.camera.target = [0.0, 0.0, 0.0];
    scene.camera.fov_y = 60.0;
    // One blade far off: the floor is what the frame shows.
    let far = upright_blade(Vec3::new(30.0, 0.0, 30.0), Vec3::X, 0.3, 0.01);
    let (w, h) = (96, 96);
    let mut frames = Vec::new();
    for on in [true, false] {
        scene.grass.look.self_shadowing = on;
        frames.push(render(&gpu, &scene, &[far], w, h, ViewMode::Shaded));
    }
    // The meadow's middle (the frame's centre) and the bare ground beyond
    // its edge (4.5 m off, inside the frame).
    let (cx, cy) = (w / 2, h / 2);
    let (sx, sy) = common::project(&scene, Vec3::new(3.0, 0.0, 0.0), w, h);
    let (sx, sy) = (sx.round() as u32, sy.round() as u32);
    let floor = |f: &meadow::frame::Frame, c| mean_linear(f, cx - 3, cy - 3, cx + 3, cy + 3, c);
    let soil = |f: &meadow::frame::Frame, c| mean_linear(f, sx - 2, sy - 2, sx + 2, sy + 2, c);
    // Beer-Lambert: leaf area index 300 x 0.55 x 0.017 x 2/3, leaves at
    // the spherical distribution's mean inclination (cos 0.5) for the sun,
    // the sky's extinction 0.8, both times sqrt(1 - 0.3) for the light the
    // leaves scatter on.
    let lai = 300.0 * 0.55 * 0.017 * (2.0 / 3.0);
    let l = glam::DVec3::from_array(scene.light.direction.map(f64::from)).normalize();
    let scatter = (1.0f64 - 0.3).sqrt();
    let sun_t = (-leaf_projection(l.y, 0.5) * scatter * lai / l.y).exp();
    let sky_t = (-0.8 * scatter * lai).exp();
    let (ambient, sun) = (
        scene.light.ambient as f64,
        scene.light.color[1] as f64 * l.y,
    );
    let expected = (ambient * sky_t + sun * sun_t) / (ambient + sun);
    let ratio = floor(&frames[0], 1) / floor(&frames[1], 1);
    eprintln!("floor with self-shadowing over without: {ratio:.3} (Beer-Lambert {expected:.3})");
    assert!(
        (ratio - expected).abs() < 0.05 * expected,
        "the floor's light under the canopy {ratio:.3}, Beer-Lambert's {expected:.3}"
    );
    // The floor is the sward's (green above red), the bare ground soil
    // (red above green), untouched by the canopy.
    let (floor_r, floor_g) = (floor(&frames[1], 0), floor(&frames[1], 1));
    let (soil_r, soil_g) = (soil(&frames[0], 0), soil(&frames[0], 1));
    assert!(
        floor_g > 1.1 * floor_r,
        "the floor under grass: r {floor_r:.4} g {floor_g:.4}"
    );
    assert!(
        soil_r > 1.1 * soil_g,
        "bare soil: r {soil_r:.4} g {soil_g:.4}"
    );
    let soil_off = soil(&frames[1], 1);
    assert!(
        (soil(&frames[0], 1) - soil_off).abs() < 1e-3,
        "the soil is not shaded"
    );
    finish(gpu);
}

/// sRGB bytes whose hue is the soil's (orange-brown, under 42 degrees,
/// and saturated): grass, litter and sky are not.
fn soil_coloured(p: [u8; 3]) -> bool {
    let [r, g, b] = p.map(f64::from);
    let (max, min) = (r.max(g).max(b), r.min(g).min(b));
    if max <= min || r < max || max < 8.0 {
        return false;
    }
    let hue = 60.0 * (g - b) / (max - min);
    let saturation = (max - min) / max;
    hue < 42.0 && saturation > 0.15
}

/// An open field from a standing eye: a cover of 40 blades a square
/// metre, the density whose bare soil showed between the strands (42% of
/// the pixels below the horizon were soil before the floor took the
/// canopy's colour). Now at most 5% are soil-coloured.
#[test]
fn an_open_cover_from_a_standing_eye_shows_grass_not_soil() {
    let gpu = strict_gpu();
    let mut scene = Scene::builtin("steppe").unwrap();
    scene.ground = Default::default();
    scene.ground.half_extent = 60.0;
    scene.camera.path.clear();
    scene.camera.position = [0.0, 1.7, 0.0];
    scene.camera.target = [20.0, 0.0, 0.0];
    scene.grass.cover = Some(Cover {
        density: Some(40.0),
        view_distance: 24.0,
        seed: None,
        simulate_radius: Some(0.0),
        size: None,
        center: None,
    });
    // No dry blades or tips: straw would read as soil by hue.
    scene.grass.look.dryness = 0.0;
    scene.grass.look.tip = 0.0;
    let (w, h) = (320, 180);
    let frame = render(&gpu, &scene, &[], w, h, ViewMode::Shaded);
    // Below the horizon: the rows under the point at the horizon's height
    // straight ahead, far off.
    let (_, horizon) = common::project(&scene, Vec3::new(2000.0, 1.7, 0.0), w, h);
    let first = horizon.ceil() as u32 + 2;
    let mut soil = 0usize;
    let mut all = 0usize;
    for y in first..h {
        for x in 0..w {
            all += 1;
            if soil_coloured(common::pixel(&frame, x, y)) {
                soil += 1;
            }
        }
    }
    let share = soil as f64 / all as f64;
    eprintln!(
        "soil-coloured below the horizon: {:.2}% of {all} pixels",
        100.0 * share
    );
    assert!(
        share <= 0.05,
        "{:.1}% of the ground is soil-coloured",
        100.0 * share
    );
    finish(gpu);
}

/// A dense meadow in strong gusts from a standing eye looking into the
/// wind (honami, cut to 8 x 6 m, its 33 frames): the shaded picture's 16 x 16 pixel
/// blocks of grass vary by 5% of their light or more over a gust period,
/// and follow their blades' displacement (median |r| at least 0.6), as
/// report.json's light_waves says.
#[test]
fn gusts_over_a_dense_meadow_send_waves_of_light_that_follow_the_motion() {
    // reproduce --quick's honami: the meadow cut to 8 x 6 m.
    let scene = meadow::commands::reproduce::honami(true).unwrap();
    let period = 1.0 / scene.wind.inflow.as_ref().unwrap().gust.frequency as f64;
    let (frames, fps, start) = (scene.render.frames, scene.render.fps, scene.render.start);
    let mut request = common::strict_request(scene, 320, 180, frames, fps);
    request.animation.start = start;
    request.light_waves = true;
    request.gif = false;
    let dir = std::env::temp_dir().join(format!("meadow-light-waves-{}", std::process::id()));
    let report = render_to_dir(&request, &dir).unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(report.validation.errors, 0);
    let waves = report.light_waves.expect("light_waves measured");
    eprintln!("{waves:?}");
    assert!(
        waves.seconds >= period,
        "a gust period ({period} s): {} s",
        waves.seconds
    );
    assert!(waves.blocks >= 40, "blocks of grass: {}", waves.blocks);
    let modulation = waves.modulation_median.unwrap();
    let r = waves.correlation_abs_median.unwrap();
    assert!(
        modulation >= 0.05,
        "the light varies by {:.2}%",
        100.0 * modulation
    );
    assert!(
        r >= 0.6,
        "the light follows the motion with median |r| {r:.2}"
    );
}
