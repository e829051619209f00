//! Which blades each pass can see, on the CPU: the reference for the cull
//! pass (src/render/cull.rs, glsl/common/cull.glsl), test for test. Every
//! test is conservative: a blade is left out only when nothing it can put
//! on screen, or cast onto what is on screen, survives.

use glam::{Mat4, Vec3, Vec4};

use crate::model::BladeVertex;
use crate::render::depth_pyramid::Level;
use crate::render::shadow_params::ShadowParams;
use crate::render::thinning::Thinning;

/// Suns lower than this (the y of the unit vector toward them) cast
/// shadows too long to bound: every blade casts.
pub const LOWEST_SWEPT_SUN: f32 = 0.02;

/// Whether a blade is drawn by the colour pass and by the shadow pass.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Visibility {
    pub in_view: bool,
    pub caster: bool,
}

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub lo: Vec3,
    pub hi: Vec3,
}

impl Bounds {
    /// Everything the geometry stage can emit for a blade: the Bezier
    /// curve (eq. 1) and its interpolated width vector lie in the hull of
    /// the control points and width vectors, and the taper only narrows.
    pub fn of_blade(v: &[BladeVertex; 4]) -> Self {
        Self::of_scaled_blade(v, 1.0)
    }

    /// As `of_blade`, the width vectors scaled by `width_scale` (the
    /// distance thinning's, src/render/thinning.rs).
    pub fn of_scaled_blade(v: &[BladeVertex; 4], width_scale: f32) -> Self {
        let mut b = Bounds {
            lo: Vec3::splat(f32::MAX),
            hi: Vec3::splat(f32::MIN),
        };
        for c in v {
            let p = Vec3::from(c.position);
            let w = Vec3::from(c.half_width).abs() * width_scale;
            b.lo = b.lo.min(p - w);
            b.hi = b.hi.max(p + w);
        }
        b
    }

    /// The box grown by its shadow: swept away from the sun (`light`
    /// points toward it, y > 0) down to the lowest ground `floor` (0 on
    /// flat ground). Whatever receives the shadow (ground, blades,
    /// obstacles) lies inside.
    pub fn shadow_sweep(self, light: Vec3, floor: f32) -> Self {
        let run = Vec3::new(light.x / light.y, 0.0, light.z / light.y);
        let (y0, y1) = (self.lo.y.max(floor) - floor, self.hi.y.max(floor) - floor);
        let shift_lo = (run * y0).min(run * y1);
        let shift_hi = (run * y0).max(run * y1);
        Bounds {
            lo: Vec3::new(
                self.lo.x.min(self.lo.x - shift_hi.x),
                self.lo.y.min(floor),
                self.lo.z.min(self.lo.z - shift_hi.z),
            ),
            hi: Vec3::new(
                self.hi.x.max(self.hi.x - shift_lo.x),
                self.hi.y,
                self.hi.z.max(self.hi.z - shift_lo.z),
            ),
        }
    }

    /// How far inside the frustum of `m` (world to Vulkan clip space:
    /// -w <= x, y <= w, 0 <= z <= w) the box reaches, by the least of the
    /// six planes read off the matrix's rows, in the planes' own units:
    /// negative when the box lies wholly outside one of them.
    /// The box grown by `by` (m) every way.
    pub fn grown(self, by: f32) -> Self {
        Bounds {
            lo: self.lo - Vec3::splat(by),
            hi: self.hi + Vec3::splat(by),
        }
    }

    pub fn frustum_margin(self, m: &Mat4) -> f32 {
        frustum_planes(m)
            .into_iter()
            .map(|plane| {
                let n = plane.truncate();
                let far_corner = Vec3::select(n.cmpge(Vec3::ZERO), self.hi, self.lo);
                n.dot(far_corner) + plane.w
            })
            .fold(f32::INFINITY, f32::min)
    }
}

impl Bounds {
    /// Whether the depth pyramid `pyramid` (every level, placed as
    /// `levels` says) of a frame seen as `seen_from` hides the box wholly
    /// (glsl/cull/flags.comp `box_occluded`): its nearest depth lies
    /// behind the farthest of every texel under its screen rectangle, at
    /// the level where that spans at most 2 x 2 texels; never when the
    /// box reaches behind that camera or out of its view. Also how near
    /// the decision came to going the other way: the least distance (in
    /// depth, or in the rectangle's normalised coordinates) of a compared
    /// value from its threshold.
    pub fn occluded(self, seen_from: &Mat4, pyramid: &[f32], levels: &[Level]) -> (bool, f32) {
        let mut rect_lo = glam::Vec2::splat(f32::MAX);
        let mut rect_hi = glam::Vec2::splat(f32::MIN);
        let mut nearest = f32::MAX;
        let mut in_front = true;
        for c in 0..8 {
            let corner = Vec3::select(
                glam::BVec3::new(c & 1 != 0, c & 2 != 0, c & 4 != 0),
                self.hi,
                self.lo,
            );
            let clip = *seen_from * corner.extend(1.0);
            in_front &= clip.w > 1e-6 && clip.z >= 0.0;
            let ndc = clip.truncate() / clip.w.max(1e-6);
            rect_lo = rect_lo.min(ndc.truncate());
            rect_hi = rect_hi.max(ndc.truncate());
            nearest = nearest.min(ndc.z);
        }
        let edge = (rect_lo + 1.0)
            .min_element()
            .min((1.0 - rect_hi).min_element());
        if !in_front || edge < 0.0 {
            return (false, edge.abs());
        }
        let base = levels[0];
        let size = glam::Vec2::new(base.width as f32, base.height as f32);
        let a = ((rect_lo * 0.5 + 0.5) * size).clamp(glam::Vec2::ZERO, size - 1.0);
        let b = ((rect_hi * 0.5 + 0.5) * size).clamp(glam::Vec2::ZERO, size - 1.0);
        let extent = (b - a).max_element();
        let level = (extent.max(1.0).log2().ceil() as usize).min(levels.len() - 1);
        let at = levels[level];
        let first = (a.x as u32 >> level, a.y as u32 >> level);
        let last = (
            (b.x as u32 >> level).min(at.width - 1),
            (b.y as u32 >> level).min(at.height - 1),
        );
        let mut farthest = 0.0f32;
        for y in first.1..=last.1 {
            for x in first.0..=last.0 {
                farthest = farthest.max(pyramid[(at.offset + y * at.width + x) as usize]);
            }
        }
        (nearest > farthest, (nearest - farthest).abs().min(edge))
    }
}

/// The six planes of the frustum of `m` (world to Vulkan clip space: -w
/// <= x, y <= w, 0 <= z <= w), read off the matrix's rows: a point p is
/// inside all of them where dot(plane, (p, 1)) >= 0.
pub fn frustum_planes(m: &Mat4) -> [Vec4; 6] {
    let [r0, r1, r2, r3] = [m.row(0), m.row(1), m.row(2), m.row(3)];
    [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2]
}

/// What the cull pass tests each blade against in one frame.
#[derive(Clone, Copy, Debug)]
pub struct CullView {
    /// World to Vulkan clip space.
    pub view_proj: Mat4,
    pub eye: Vec3,
    /// Toward the sun, unit length.
    pub light: Vec3,
    /// The lowest ground shadows fall on (`frame.terrain_lowest`; 0 on flat ground).
    pub floor: f32,
    /// Whether the shadow pass draws (else no blade casts).
    pub shadows: bool,
    pub thinning: Thinning,
    /// The orientation test's cosine (1 = off): `least_alignment`.
    pub edge_on: f32,
    /// How far (m) the shadow map's filter reads beyond a receiver
    /// (`filter_reach`): a blade whose shadow falls that near the view
    /// still darkens what the view sees, a little.
    pub filter_reach: f32,
}

/// How far (m) the shadow map's filter reaches around a receiver: the
/// PCF taps' spacing plus a bilinear texel and one more, in the world's
/// metres along the light's axes (`light_view_proj`: world to the map's
/// clip space, orthographic). 0 without shadows.
pub fn filter_reach(light_view_proj: &Mat4, shadow: ShadowParams) -> f32 {
    if !shadow.on {
        return 0.0;
    }
    let row = |i: usize| light_view_proj.row(i).truncate().length();
    // Clip space spans 2 across the map, uv 1.
    let texel_m = shadow.texel * 2.0 / row(0).min(row(1)).max(1e-12);
    texel_m * (shadow.pcf_radius + 2.0)
}

/// How near each decision about a blade came to going the other way, so
/// a test comparing with the GPU can tell rounding from a wrong answer.
#[derive(Clone, Copy, Debug)]
pub struct Margins {
    /// The smallest frustum margin any decision was taken by
    /// (`Bounds::frustum_margin`).
    pub frustum: f32,
    /// The distance thinning's (`Thinning::scale`).
    pub thinning: f32,
    /// The least distance of an alignment from `edge_on`.
    pub edge_on: f32,
}

impl CullView {
    /// The cull pass's tests for one blade (glsl/common/cull.glsl
    /// `cull_flags`): a blade the distance thinning drops, or one without
    /// width, is in neither list, the bounds hold the widened blade; a
    /// blade seen edge-on from the camera is not drawn in colour, one
    /// edge-on to the sun casts no shadow.
    pub fn test(&self, v: &[BladeVertex; 4]) -> (Visibility, Margins) {
        let root = Vec3::from(v[0].position);
        let (width_scale, thin_margin) = self.thinning.scale(root, v[0].blade_rand, self.eye);
        let to_eye = v.map(|c| Vec3::from(c.position) - self.eye);
        let (from_eye, from_sun) = (
            least_alignment(v, to_eye),
            least_alignment(v, [self.light; 4]),
        );
        let mut margins = Margins {
            frustum: f32::INFINITY,
            thinning: thin_margin,
            edge_on: (from_eye - self.edge_on)
                .abs()
                .min((from_sun - self.edge_on).abs()),
        };
        if width_scale <= 0.0 || !crate::model::has_width(v) {
            return (Visibility::default(), margins);
        }
        let bounds = Bounds::of_scaled_blade(v, width_scale);
        let margin = bounds.frustum_margin(&self.view_proj);
        let mut seen = Visibility {
            in_view: margin >= 0.0 && from_eye <= self.edge_on,
            caster: false,
        };
        margins.frustum = margin.abs();
        if self.shadows && from_sun <= self.edge_on {
            match self.shadow_box(bounds) {
                None => seen.caster = true,
                Some(swept) => {
                    let swept = swept.frustum_margin(&self.view_proj);
                    seen.caster = swept >= 0.0;
                    margins.frustum = margins.frustum.min(swept.abs());
                }
            }
        }
        (seen, margins)
    }

    /// The box a blade of `bounds` can cast its shadow into, the shadow
    /// map filter's reach included: its bounds swept away from the sun
    /// down to the lowest ground (glsl/common/cull.glsl's `swept_lo`
    /// and `swept_hi`). None with a sun too low to bound the sweep.
    pub fn shadow_box(&self, bounds: Bounds) -> Option<Bounds> {
        (self.light.y >= LOWEST_SWEPT_SUN).then(|| {
            bounds
                .shadow_sweep(self.light, self.floor)
                .grown(self.filter_reach)
        })
    }
}

/// How nearly a blade is seen edge-on along `dir[i]` (toward each control
/// point): the least |cos| between its width vector and those directions,
/// 0 where a width vector or direction is zero (a blade without width is
/// counted as face-on: it emits nothing anyway).
pub fn least_alignment(v: &[BladeVertex; 4], dir: [Vec3; 4]) -> f32 {
    let mut least = 1.0f32;
    for (c, d) in v.iter().zip(dir) {
        let w = Vec3::from(c.half_width);
        let norms = d.length_squared() * w.length_squared();
        let cos = if norms > 0.0 {
            d.dot(w).abs() / norms.sqrt()
        } else {
            0.0
        };
        least = least.min(cos);
    }
    least
}

/// The frustum and shadow tests alone for one blade under the camera
/// `view_proj` and the sun `light` (toward it, unit length), the shadow
/// test only with `shadows`: no thinning, no orientation test. Also the
/// smallest frustum margin any decision was taken by.
pub fn visibility(
    v: &[BladeVertex; 4],
    view_proj: &Mat4,
    light: Vec3,
    shadows: bool,
) -> (Visibility, f32) {
    let view = CullView {
        view_proj: *view_proj,
        eye: Vec3::ZERO,
        light,
        floor: 0.0,
        shadows,
        thinning: Thinning::OFF,
        edge_on: 1.0,
        filter_reach: 0.0,
    };
    let (seen, margins) = view.test(v);
    (seen, margins.frustum)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn upright(at: Vec3, height: f32) -> [BladeVertex; 4] {
        std::array::from_fn(|i| BladeVertex {
            position: (at + Vec3::Y * height * i as f32 / 3.0).to_array(),
            blade_rand: 0.5,
            half_width: [0.01, 0.0, 0.0],
            displacement: 0.0,
        })
    }

    fn camera() -> Mat4 {
        // At 2 m height looking along -z.
        let view = Mat4::look_at_rh(
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.0, 0.0, -10.0),
            Vec3::Y,
        );
        let mut proj = Mat4::perspective_rh(45f32.to_radians(), 16.0 / 9.0, 0.05, 200.0);
        proj.y_axis.y = -proj.y_axis.y;
        proj * view
    }

    #[test]
    fn a_blade_ahead_is_seen_and_one_behind_is_not() {
        let sun = Vec3::new(0.0, 1.0, 0.0);
        let (ahead, _) = visibility(
            &upright(Vec3::new(0.0, 0.0, -5.0), 0.5),
            &camera(),
            sun,
            true,
        );
        let (behind, _) = visibility(
            &upright(Vec3::new(0.0, 0.0, 5.0), 0.5),
            &camera(),
            sun,
            true,
        );
        assert_eq!(
            ahead,
            Visibility {
                in_view: true,
                caster: true
            }
        );
        assert_eq!(behind, Visibility::default());
    }

    #[test]
    fn a_blade_without_width_is_in_neither_list() {
        let sun = Vec3::new(0.0, 1.0, 0.0);
        let mut ahead = upright(Vec3::new(0.0, 0.0, -5.0), 0.5);
        for v in &mut ahead {
            v.half_width = [0.0; 3];
        }
        let (seen, _) = visibility(&ahead, &camera(), sun, true);
        assert_eq!(seen, Visibility::default());
    }

    #[test]
    fn a_blade_out_of_view_casts_into_it_when_its_shadow_falls_there() {
        // 20 m to the left, out of a 45 degree view at 10 m ahead; a low
        // sun on the far left throws a 1 m blade's shadow 20 m to the right.
        let blade = upright(Vec3::new(-24.0, 0.0, -10.0), 1.0);
        let toward_sun = Vec3::new(-20.0, 1.0, 0.0).normalize();
        let (seen, _) = visibility(&blade, &camera(), toward_sun, true);
        assert_eq!(
            seen,
            Visibility {
                in_view: false,
                caster: true
            }
        );
        // With the sun on the other side the shadow falls away from view.
        let (seen, _) = visibility(
            &blade,
            &camera(),
            toward_sun * Vec3::new(-1.0, 1.0, 1.0),
            true,
        );
        assert_eq!(seen, Visibility::default());
        // Without shadows nothing casts.
        let (seen, _) = visibility(&blade, &camera(), toward_sun, false);
        assert!(!seen.caster);
    }

    #[test]
    fn the_sweep_reaches_the_ground_where_the_tip_shadow_falls() {
        let b = Bounds::of_blade(&upright(Vec3::ZERO, 1.0));
        let light = Vec3::new(1.0, 1.0, -0.5).normalize();
        let s = b.shadow_sweep(light, 0.0);
        // The tip (0, 1, 0) lands at (-1, 0, 0.5).
        assert!((s.lo.x - (-1.0 - 0.01)).abs() < 1e-6, "{s:?}");
        assert!((s.hi.z - 0.5).abs() < 1e-6, "{s:?}");
        assert_eq!(s.lo.y, 0.0);
        assert_eq!(s.hi.y, 1.0);
    }

    #[test]
    fn a_blade_seen_edge_on_is_left_out_of_the_pass_that_sees_it_so() {
        // Width along x; the camera at (0, 2, 0) looks along -z.
        let sun = Vec3::new(1.0, 1.0, 0.0).normalize();
        let view = |at: Vec3, width: Vec3| {
            let mut blade = upright(at, 0.5);
            for c in &mut blade {
                c.half_width = width.to_array();
            }
            CullView {
                view_proj: camera(),
                eye: Vec3::new(0.0, 2.0, 0.0),
                light: sun,
                floor: 0.0,
                shadows: true,
                thinning: Thinning::OFF,
                edge_on: 0.9,
                filter_reach: 0.0,
            }
            .test(&blade)
            .0
        };
        // Across the view: seen, and its width 45 degrees from the sun: casts.
        let across = view(Vec3::new(0.0, 0.0, -5.0), Vec3::new(0.01, 0.0, 0.0));
        assert_eq!(
            across,
            Visibility {
                in_view: true,
                caster: true
            }
        );
        // Width along the view ray (and 90 degrees from the sun): casts,
        // not drawn.
        let along = view(Vec3::new(0.0, 0.0, -5.0), Vec3::new(0.0, -0.0035, -0.01));
        assert_eq!(
            along,
            Visibility {
                in_view: false,
                caster: true
            }
        );
        // Width along the sun's rays: drawn, casts nothing.
        let sunward = view(Vec3::new(0.0, 0.0, -5.0), sun * 0.01);
        assert!(sunward.in_view && !sunward.caster, "{sunward:?}");
        // No width: no blade (the cover's beyond its bounds), in neither.
        let none = view(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO);
        assert_eq!(none, Visibility::default());
    }

    #[test]
    fn a_blade_beyond_the_far_plane_or_before_the_near_plane_is_not_seen() {
        let sun = Vec3::Y;
        let (far, _) = visibility(
            &upright(Vec3::new(0.0, 0.0, -300.0), 0.5),
            &camera(),
            sun,
            false,
        );
        assert!(!far.in_view);
        // A blade that is only width beside the eye, behind the near plane.
        let near = upright(Vec3::new(0.0, 1.9, 0.04), 0.05);
        assert!(!visibility(&near, &camera(), sun, false).0.in_view);
    }
}
