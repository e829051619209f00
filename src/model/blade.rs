//! The grass model of the paper (section 3.1; docs/method.md section 2): a blade
//! is a cubic Bezier curve with control points P0 (root) .. P3 (tip), and
//! each of its three edges P_i P_{i+1} carries an orthonormal frame
//! (E_e along the edge, E_w across the blade, E_n its face normal).

use glam::Vec3;

/// Vertical, the ground normal.
pub const UP: Vec3 = Vec3::Y;

/// How far inside contact's region a fitted rest shape keeps each control
/// point (`Blade::fitted`): n . d - c |d|^2 at least this times |d|, about
/// half a degree of lean; the cover's fit to the ground's heights
/// (`scene::cover::fitted`, which its tile kernel does alike) keeps the
/// same room.
pub use crate::interface::{
    COVER_FIT_SAMPLES, COVER_FIT_SHRINKS, COVER_FIT_TURNS, COVER_HOLD_HALVINGS, FIT_ROOM,
};

/// The three shapes one cubic with one inflection point covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BladeKind {
    Upright,
    Curved,
    Drooping,
}

/// The orientation of one edge (docs/method.md section 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeFrame {
    /// Along the edge, P_i -> P_{i+1}.
    pub e: Vec3,
    /// The blade's width direction, orthogonal to `e`.
    pub w: Vec3,
    /// The face normal, `normalize(w x e)`.
    pub n: Vec3,
}

/// One blade in its rest shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blade {
    /// Control points P0 (root, on the ground) .. P3 (tip).
    pub rest: [Vec3; 4],
    /// Half the blade's width at the root.
    pub half_width: f32,
    /// Unit horizontal vector across the blade: E_w of every rest edge
    /// (bending happens in the plane spanned by UP and `facing`).
    pub width_dir: Vec3,
    pub kind: BladeKind,
    /// A per-blade random value in [0, 1), for colour variation.
    pub rand: f32,
    /// The ground's upward unit normal at the root (UP on flat ground):
    /// the axis the blade swings about, and with `ground_curvature` what
    /// ground contact keeps the blade above.
    pub ground: Vec3,
    /// c (1/m): ground contact keeps every control point P in the region
    /// n . (P - P0) >= c |P - P0|^2 over the tangent plane at the root, a
    /// paraboloid the ground within the blade's reach lies under (0 on
    /// flat ground: the plane itself). The region is convex, so the curve,
    /// inside its control points' hull, stays in it too.
    pub ground_curvature: f32,
}

impl Blade {
    /// Builds a blade rooted at `root`, leaning toward the horizontal unit
    /// vector `facing`, from a 2D profile given as (along facing, up) pairs.
    pub fn from_profile(
        root: Vec3,
        facing: Vec3,
        profile: [[f32; 2]; 4],
        half_width: f32,
        kind: BladeKind,
        rand: f32,
    ) -> Self {
        let rest = profile.map(|[x, y]| root + facing * x + UP * y);
        Self {
            rest,
            half_width,
            width_dir: UP.cross(facing).normalize(),
            kind,
            rand,
            ground: UP,
            ground_curvature: 0.0,
        }
    }

    /// The same blade moved up by `height` (rooted on terrain, growing
    /// upright as grass does on a slope) over ground of upward unit normal
    /// `ground` whose rise over its tangent plane within the blade's reach
    /// is at most `curvature` times the distance squared (`ground_curvature`;
    /// held to what leaves each rest point `FIT_ROOM` a metre inside
    /// contact's region, so a blade is never in contact at rest, nor on
    /// the region's boundary, where a wind pressing it toward the ground
    /// would hold it still).
    pub fn raised(mut self, height: f32, ground: Vec3, curvature: f32) -> Self {
        for p in &mut self.rest {
            p.y += height;
        }
        self.ground = ground;
        let root = self.rest[0];
        let rest_room = self.rest[1..]
            .iter()
            .map(|&p| {
                let d = p - root;
                (d.dot(ground) - FIT_ROOM * d.length()) / d.length_squared().max(1e-12)
            })
            .fold(f32::MAX, f32::min);
        self.ground_curvature = curvature.min(rest_room).max(0.0);
        self
    }

    /// The rest shape fitted to the ground it stands on (after `raised`,
    /// `curvature` the ground's rise over its tangent plane within the
    /// blade's reach): where a control point lies outside contact's region
    /// (a blade leaning or drooping into a slope, which would stand in the
    /// hill, held there by contact and never moving), the blade is turned
    /// about the vertical through its root as little as fits, its lean then
    /// across or down the slope as grass on a slope hangs; where no turn
    /// fits (a hollow tighter than the blade), its lean, turned where it
    /// fits best, is shrunk toward upright as far as needed. Every control
    /// point then keeps `FIT_ROOM` inside the region, and so does the drawn
    /// curve (the region is convex); the blade stays upright at its root,
    /// its width horizontal, and contact takes the ground's whole
    /// `curvature`. A blade that fits is returned as it is.
    pub fn fitted(self, curvature: f32) -> Self {
        let (n, root) = (self.ground, self.rest[0]);
        let room = |b: &Blade| {
            b.rest[1..]
                .iter()
                .map(|&p| {
                    let d = p - root;
                    (n.dot(d) - curvature * d.length_squared()) / d.length().max(1e-9)
                })
                .fold(f32::MAX, f32::min)
        };
        if room(&self) >= FIT_ROOM {
            return self;
        }
        let turned = |angle: f32| {
            let q = glam::Quat::from_rotation_y(angle);
            Blade {
                rest: self.rest.map(|p| root + q * (p - root)),
                width_dir: q * self.width_dir,
                ..self
            }
        };
        const TURNS: u32 = 32;
        let fit = |b: Blade| b.raised(0.0, n, curvature);
        for k in 1..=TURNS {
            let angle = std::f32::consts::PI * k as f32 / TURNS as f32;
            for b in [turned(angle), turned(-angle)] {
                if room(&b) >= FIT_ROOM {
                    return fit(b);
                }
            }
        }
        let best = (0..2 * TURNS)
            .map(|k| turned(std::f32::consts::PI * k as f32 / TURNS as f32))
            .max_by(|a, b| room(a).total_cmp(&room(b)))
            .unwrap_or(self);
        let shrunk = |t: f32| Blade {
            rest: best.rest.map(|p| {
                let d = p - root;
                root + Vec3::new(d.x * t, d.y, d.z * t)
            }),
            ..best
        };
        const SHRINKS: u32 = 16;
        (1..=SHRINKS)
            .map(|k| shrunk(1.0 - k as f32 / SHRINKS as f32))
            .find(|b| room(b) >= FIT_ROOM)
            .map_or_else(|| fit(shrunk(0.0)), fit)
    }

    /// The farthest any point of the blade can get from its root: its
    /// edges' lengths end to end.
    pub fn reach(&self) -> f32 {
        self.rest.windows(2).map(|e| (e[1] - e[0]).length()).sum()
    }

    /// The rest frame of each edge.
    pub fn rest_frames(&self) -> [EdgeFrame; 3] {
        std::array::from_fn(|i| edge_frame(self.rest[i], self.rest[i + 1], self.width_dir))
    }

    /// Point on the curve, paper eq. 1.
    pub fn bezier(&self, t: f32) -> Vec3 {
        bezier(&self.rest, t)
    }

    /// The four control points as the render pipeline's vertices.
    pub fn vertices(&self) -> [BladeVertex; 4] {
        std::array::from_fn(|i| BladeVertex {
            position: self.rest[i].to_array(),
            blade_rand: self.rand,
            half_width: (self.width_dir * self.half_width).to_array(),
            displacement: 0.0,
        })
    }

    pub fn edge_lengths(&self) -> [f32; 3] {
        std::array::from_fn(|i| self.rest[i].distance(self.rest[i + 1]))
    }
}

/// E_e, E_w, E_n of the edge a -> b; `width_dir` is re-orthogonalised
/// against the edge. Guarded: a zero-length edge gets the vertical frame.
pub fn edge_frame(a: Vec3, b: Vec3, width_dir: Vec3) -> EdgeFrame {
    let e = (b - a).try_normalize().unwrap_or(UP);
    let w = (width_dir - e * e.dot(width_dir))
        .try_normalize()
        .unwrap_or_else(|| e.any_orthonormal_vector());
    let n = w.cross(e).normalize();
    EdgeFrame { e, w, n }
}

/// B(t) = (1-t)^3 P0 + 3(1-t)^2 t P1 + 3(1-t) t^2 P2 + t^3 P3 (paper eq. 1).
pub fn bezier(p: &[Vec3; 4], t: f32) -> Vec3 {
    let s = 1.0 - t;
    p[0] * (s * s * s) + p[1] * (3.0 * s * s * t) + p[2] * (3.0 * s * t * t) + p[3] * (t * t * t)
}

/// One control point as the render pipeline reads it (src/interface/defs.rs).
pub use crate::interface::BladeVertex;

/// Whether a blade's control points (from its root's on) have width: one
/// without (the cover's beyond its bounds, `scene::cover::left_out`) is
/// no blade, which the cull pass lists in neither pass
/// (glsl/common/cull.glsl tests the same).
pub fn has_width(blade: &[BladeVertex]) -> bool {
    blade[0].half_width != [0.0; 3]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rest_frames_are_orthonormal_and_normal_faces_the_lean() {
        let facing = Vec3::new(1.0, 0.0, 0.0);
        let blade = Blade::from_profile(
            Vec3::ZERO,
            facing,
            [[0.0, 0.0], [0.05, 0.3], [0.3, 0.55], [0.6, 0.35]],
            0.01,
            BladeKind::Drooping,
            0.5,
        );
        for f in blade.rest_frames() {
            assert!((f.e.length() - 1.0).abs() < 1e-6);
            assert!((f.w.length() - 1.0).abs() < 1e-6);
            assert!((f.n.length() - 1.0).abs() < 1e-6);
            assert!(
                f.e.dot(f.w).abs() < 1e-6 && f.e.dot(f.n).abs() < 1e-6 && f.w.dot(f.n).abs() < 1e-6
            );
        }
        // For an upward edge, E_n = E_w x E_e points the way the blade leans.
        let upright = edge_frame(Vec3::ZERO, UP, blade.width_dir);
        assert!(upright.n.dot(facing) > 0.999);
    }

    #[test]
    fn bezier_interpolates_root_and_tip() {
        let p = [
            Vec3::ZERO,
            Vec3::Y,
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::new(2.0, 1.0, 0.0),
        ];
        assert_eq!(bezier(&p, 0.0), p[0]);
        assert_eq!(bezier(&p, 1.0), p[3]);
        let mid = bezier(&p, 0.5);
        assert!((mid - Vec3::new(0.625, 1.25, 0.0)).length() < 1e-6);
    }

    #[test]
    fn degenerate_edge_is_guarded() {
        let f = edge_frame(Vec3::ONE, Vec3::ONE, Vec3::X);
        assert!(f.e.is_finite() && f.w.is_finite() && f.n.is_finite());
    }

    /// A drooping blade hanging uphill on a 27 degree slope reaches into
    /// the ground: fitted, it is turned about its vertical (its shape, its
    /// upright root and its horizontal width kept) until every control
    /// point keeps `FIT_ROOM` inside contact's region, and contact takes
    /// the ground's whole rise; a blade hanging downhill fits as it is;
    /// and in a hollow tighter than any turn, the lean shrinks.
    #[test]
    fn a_blade_hanging_into_a_slope_is_turned_away_from_it() {
        let slope = 27f32.to_radians();
        // The ground rises toward +x: its normal leans toward -x.
        let n = Vec3::new(-slope.sin(), slope.cos(), 0.0);
        let profile = [[0.0, 0.0], [0.02, 0.3], [0.3, 0.45], [0.55, 0.15]];
        let hanging = |facing: Vec3| {
            Blade::from_profile(Vec3::ZERO, facing, profile, 0.01, BladeKind::Drooping, 0.5)
                .raised(0.0, n, 0.05)
        };
        let room = |b: &Blade, c: f32| {
            b.rest[1..]
                .iter()
                .map(|&d| (n.dot(d) - c * d.length_squared()) / d.length())
                .fold(f32::MAX, f32::min)
        };
        let uphill = hanging(Vec3::X);
        assert!(room(&uphill, 0.05) < 0.0, "the tip is not in the slope");
        let fitted = uphill.fitted(0.05);
        assert!(room(&fitted, 0.05) >= FIT_ROOM, "{}", room(&fitted, 0.05));
        assert_eq!(fitted.ground_curvature, 0.05);
        assert_eq!(fitted.kind, BladeKind::Drooping);
        for (a, b) in fitted.edge_lengths().iter().zip(uphill.edge_lengths()) {
            assert!((a - b).abs() < 1e-5);
        }
        assert!(fitted.width_dir.y.abs() < 1e-6 && (fitted.width_dir.length() - 1.0).abs() < 1e-5);
        for i in 0..4 {
            // Turned about the vertical: each point's height kept.
            assert!((fitted.rest[i].y - uphill.rest[i].y).abs() < 1e-6);
        }
        let downhill = hanging(-Vec3::X);
        assert_eq!(downhill.fitted(0.05), downhill);
        // A hollow curving up faster than any turn leaves room for: the
        // lean shrinks toward upright.
        let pit = uphill.fitted(2.0);
        let lean = |b: &Blade| Vec3::new(b.rest[3].x, 0.0, b.rest[3].z).length();
        assert!(
            lean(&pit) < lean(&uphill),
            "{} {}",
            lean(&pit),
            lean(&uphill)
        );
    }
}
