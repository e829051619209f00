//! The sun's view for the shadow map (paper section 5), fitted to what the
//! camera sees (issue 18): an orthographic view from the sun whose sides
//! hold only the part of the grass's box inside the camera's frustum, so
//! the map's texels land where they are looked at.
//!
//! A shadow seen on screen falls on a receiver in view, and the blade
//! casting it lies on the ray from that receiver toward the sun: in the
//! sun's orthographic view both have the same x and y. So the map's x and
//! y need to cover the receivers in view and nothing more; its depth range
//! stays the whole scene's, from the sun's eye past the ground.
//!
//! The side is rounded up to a power of 2^(1/8) of the map's and its
//! corner snapped to whole texels, so a moving camera changes the texels'
//! size only in steps and otherwise slides the map by whole texels: the
//! shadows do not shimmer.

use glam::{Mat4, Vec3, Vec4};

use crate::render::visibility::frustum_planes;
use crate::scene::Scene;

/// The grass's box: its footprint grown by the tallest blade (which may
/// lean that far), from the lowest ground under it up to the tallest blade
/// over the highest (flat ground: 0 to the tallest blade). Every shadow
/// the map holds falls inside it.
pub fn receiver_box(scene: &Scene) -> (Vec3, Vec3) {
    let (lo, hi) = scene.grass_reach_bounds();
    let h = scene.grass.shape.height[1];
    let step = ((hi[0] - lo[0]).max(hi[1] - lo[1]) / 256.0).max(0.01);
    let (low, high) = scene.ground.terrain().range_over(lo, hi, step);
    (
        Vec3::new(lo[0], low, lo[1]),
        Vec3::new(hi[0], high + h, hi[1]),
    )
}

/// World to the shadow map's clip space for the camera `view_proj` (world
/// to Vulkan clip space), fitted as the module says. Where the camera sees
/// all of the box, or none of it, the map holds the whole box.
pub fn light_view_proj(scene: &Scene, view_proj: &Mat4) -> Mat4 {
    let dir = Vec3::from(scene.light.direction)
        .try_normalize()
        .unwrap_or(Vec3::Y);
    let (min, max) = receiver_box(scene);
    let center = (min + max) * 0.5;
    let radius = (max - min).length() * 0.5;
    let up = if dir.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    let view = Mat4::look_at_rh(center + dir * 2.0 * radius, center, up);
    let (box_lo, box_hi) = light_extent(&view, &box_corners(min, max));
    // The view looks down -z from 2 radii away: the near plane at the eye
    // keeps whatever stands above the box (a blade taller than the
    // scene's shapes) in the map; the far plane reaches well past the
    // ground so shadows cast there are found.
    let (near, far) = (0.0, -box_lo.z + 8.0 * radius);
    let seen = seen_part(min, max, view_proj);
    let (lo, hi) =
        fit(&view, &seen, box_lo, box_hi, scene.light.shadow_map).unwrap_or((box_lo, box_hi));
    Mat4::orthographic_rh(lo.x, hi.x, lo.y, hi.y, near, far) * view
}

/// The square the map covers in the sun's view (x and y; z unused) for
/// the receivers `seen`, or `None` where it would be no smaller than the
/// whole box's rectangle `box_lo..box_hi`.
fn fit(view: &Mat4, seen: &[Vec3], box_lo: Vec3, box_hi: Vec3, map: u32) -> Option<(Vec3, Vec3)> {
    if seen.is_empty() {
        return None;
    }
    let (lo, hi) = light_extent(view, seen);
    let texels = map.max(1) as f32;
    // Two texels of room for the snapping below, then up to the next step.
    let need = (hi.x - lo.x).max(hi.y - lo.y) * (1.0 + 2.0 / texels);
    let side = 2f32.powf((8.0 * need.max(1e-3).log2()).ceil() / 8.0);
    if side >= (box_hi.x - box_lo.x).max(box_hi.y - box_lo.y) {
        return None;
    }
    let texel = side / texels;
    let x0 = (lo.x / texel).floor() * texel;
    let y0 = (lo.y / texel).floor() * texel;
    Some((Vec3::new(x0, y0, 0.0), Vec3::new(x0 + side, y0 + side, 0.0)))
}

/// The eight corners of the box `min..max`.
fn box_corners(min: Vec3, max: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    })
}

/// The least and greatest coordinates of `points` in the space of `view`.
fn light_extent(view: &Mat4, points: &[Vec3]) -> (Vec3, Vec3) {
    points.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), &p| {
            let q = view.transform_point3(p);
            (lo.min(q), hi.max(q))
        },
    )
}

/// The corners of the part of the box `min..max` inside the frustum of
/// `view_proj`: each face of either solid clipped by the other's planes.
/// The clipped faces of two convex solids bound their intersection, so
/// its corners are among these points. Empty when they do not meet.
pub fn seen_part(min: Vec3, max: Vec3, view_proj: &Mat4) -> Vec<Vec3> {
    let box_planes = [
        Vec4::new(1.0, 0.0, 0.0, -min.x),
        Vec4::new(-1.0, 0.0, 0.0, max.x),
        Vec4::new(0.0, 1.0, 0.0, -min.y),
        Vec4::new(0.0, -1.0, 0.0, max.y),
        Vec4::new(0.0, 0.0, 1.0, -min.z),
        Vec4::new(0.0, 0.0, -1.0, max.z),
    ];
    let inverse = view_proj.inverse();
    let ndc = box_corners(Vec3::new(-1.0, -1.0, 0.0), Vec3::ONE);
    let frustum_corners = ndc.map(|c| inverse.project_point3(c));
    let view_planes = frustum_planes(view_proj);
    let mut points = Vec::new();
    for face in faces(&box_corners(min, max)) {
        points.extend(clip(face.to_vec(), &view_planes));
    }
    for face in faces(&frustum_corners) {
        points.extend(clip(face.to_vec(), &box_planes));
    }
    points
}

/// The six faces of a hexahedron whose corners are numbered as
/// `box_corners` numbers them (bit 0: x, bit 1: y, bit 2: z), each as a
/// loop of four corners.
fn faces(c: &[Vec3; 8]) -> [[Vec3; 4]; 6] {
    [
        [c[0], c[2], c[6], c[4]],
        [c[1], c[3], c[7], c[5]],
        [c[0], c[1], c[5], c[4]],
        [c[2], c[3], c[7], c[6]],
        [c[0], c[1], c[3], c[2]],
        [c[4], c[5], c[7], c[6]],
    ]
}

/// The convex polygon `polygon` clipped to the side of each plane where
/// dot(plane, (p, 1)) >= 0 (Sutherland and Hodgman).
fn clip(mut polygon: Vec<Vec3>, planes: &[Vec4]) -> Vec<Vec3> {
    for plane in planes {
        let side = |p: Vec3| plane.truncate().dot(p) + plane.w;
        let mut kept = Vec::with_capacity(polygon.len() + 1);
        for (i, &a) in polygon.iter().enumerate() {
            let b = polygon[(i + 1) % polygon.len()];
            let (sa, sb) = (side(a), side(b));
            if sa >= 0.0 {
                kept.push(a);
            }
            if (sa >= 0.0) != (sb >= 0.0) {
                kept.push(a + (b - a) * (sa / (sa - sb)));
            }
        }
        polygon = kept;
        if polygon.is_empty() {
            break;
        }
    }
    polygon
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Scene {
        Scene::builtin("table1").expect("table1 is shipped")
    }

    /// The scene's camera at 16:9, as the colour pass sees it.
    fn camera(scene: &Scene) -> Mat4 {
        camera_moved(scene, Vec3::ZERO)
    }

    /// The same, eye and target moved by `d`.
    fn camera_moved(scene: &Scene, d: Vec3) -> Mat4 {
        let mut proj =
            Mat4::perspective_rh(scene.camera.fov_y.to_radians(), 16.0 / 9.0, 0.05, 200.0);
        proj.y_axis.y = -proj.y_axis.y;
        let (eye, target) = (
            Vec3::from(scene.camera.position),
            Vec3::from(scene.camera.target),
        );
        proj * Mat4::look_at_rh(eye + d, target + d, Vec3::Y)
    }

    /// Points spread through the box, kept where the camera sees them.
    fn seen_samples(scene: &Scene, view_proj: &Mat4) -> Vec<Vec3> {
        let (min, max) = receiver_box(scene);
        let n = 40;
        let mut seen = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                for k in 0..=4 {
                    let f = Vec3::new(i as f32, k as f32 * 10.0, j as f32) / n as f32;
                    let p = min + (max - min) * f;
                    let c = *view_proj * p.extend(1.0);
                    if c.w > 0.0 && c.x.abs() <= c.w && c.y.abs() <= c.w && c.z >= 0.0 && c.z <= c.w
                    {
                        seen.push(p);
                    }
                }
            }
        }
        seen
    }

    #[test]
    fn every_receiver_the_camera_sees_is_in_the_fitted_map() {
        let scene = scene();
        let view_proj = camera(&scene);
        let light = light_view_proj(&scene, &view_proj);
        let samples = seen_samples(&scene, &view_proj);
        assert!(samples.len() > 100, "{} samples seen", samples.len());
        for p in samples {
            let c = light * p.extend(1.0);
            assert!(
                c.x.abs() <= 1.0 && c.y.abs() <= 1.0 && (0.0..=1.0).contains(&c.z),
                "{p} seen by the camera lands at {c} in the shadow map"
            );
        }
    }

    #[test]
    fn the_fitted_map_is_smaller_than_the_whole_field_when_part_is_seen() {
        let scene = scene();
        let view_proj = camera(&scene);
        // The area of the map in world units, from its x and y axes'
        // scales, against the whole box's (seen by a camera above it all).
        let fitted = light_view_proj(&scene, &view_proj);
        let everything = light_view_proj(&scene, &above_it_all(&scene));
        let area = |m: &Mat4| 4.0 / (m.x_axis.truncate().length() * m.y_axis.truncate().length());
        let ratio = area(&fitted) / area(&everything);
        assert!(
            ratio < 0.75,
            "the fitted map covers {ratio:.2} of the whole box's area"
        );
    }

    /// An orthographic camera looking down on the whole box.
    fn above_it_all(scene: &Scene) -> Mat4 {
        let (min, max) = receiver_box(scene);
        let c = (min + max) * 0.5;
        let half = (max - min) * 0.5 + 1.0;
        Mat4::orthographic_rh(-half.x, half.x, -half.z, half.z, 0.0, 100.0)
            * Mat4::look_at_rh(c + Vec3::Y * 50.0, c, Vec3::NEG_Z)
    }

    #[test]
    fn a_camera_that_sees_the_whole_field_gets_the_whole_box() {
        let scene = scene();
        let (min, max) = receiver_box(&scene);
        let corners = seen_part(min, max, &above_it_all(&scene));
        let (lo, hi) = corners.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        assert!((lo - min).abs().max_element() < 1e-3, "{lo} vs {min}");
        assert!((hi - max).abs().max_element() < 1e-3, "{hi} vs {max}");
    }

    #[test]
    fn a_camera_looking_away_from_the_field_sees_none_of_it() {
        let scene = scene();
        let (min, max) = receiver_box(&scene);
        let mut proj = Mat4::perspective_rh(0.8, 1.0, 0.05, 200.0);
        proj.y_axis.y = -proj.y_axis.y;
        let away = proj
            * Mat4::look_at_rh(
                Vec3::new(0.0, 1.0, max.z + 10.0),
                Vec3::new(0.0, 1.0, max.z + 20.0),
                Vec3::Y,
            );
        assert!(seen_part(min, max, &away).is_empty());
    }

    #[test]
    fn a_moving_camera_slides_the_map_by_whole_texels() {
        let scene = scene();
        let size = scene.light.shadow_map as f32;
        let at = |shift: f32| light_view_proj(&scene, &camera_moved(&scene, Vec3::X * shift));
        let (a, b) = (at(0.0), at(0.003));
        // Same texel size; the origin moved by a whole number of texels.
        assert_eq!(a.x_axis, b.x_axis);
        let texels = (a.w_axis.x - b.w_axis.x) * size / 2.0;
        assert!(
            (texels - texels.round()).abs() < 0.05,
            "the map moved {texels} texels"
        );
    }
}
