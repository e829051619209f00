//! Motion along waypoints, shared by what moves through the meadow: a
//! wind source (src/model/wind/drive.rs) and a collider (src/model/contact.rs). The
//! GPU's twin is glsl/common/path.glsl.

use glam::Vec3;

/// The most waypoints of a path (src/interface/defs.rs: the GPU records
/// hold as many).
pub use crate::interface::MAX_PATH_POINTS;

/// Where a point moving at `speed` through the waypoints `path` is at time
/// t, its velocity, and the distance it has travelled: round and round when
/// `closed` (the last point leads back to the first), else once, stopping
/// at the end. With fewer than two points or no speed it stays at the
/// first point, or at `fallback` without one. A wind source is always
/// closed.
pub fn along_path(
    path: &[Vec3],
    speed: f32,
    closed: bool,
    t: f32,
    fallback: Vec3,
) -> (Vec3, Vec3, f32) {
    let n = path.len();
    if n < 2 || speed <= 0.0 {
        return (path.first().copied().unwrap_or(fallback), Vec3::ZERO, 0.0);
    }
    let segments = if closed { n } else { n - 1 };
    let mut total = 0.0f32;
    for i in 0..segments {
        total += path[i].distance(path[(i + 1) % n]);
    }
    if total <= 0.0 {
        return (path[0], Vec3::ZERO, 0.0);
    }
    let travelled = speed * t;
    let (mut s, moving) = if closed {
        (travelled.rem_euclid(total), true)
    } else if travelled < total {
        (travelled, true)
    } else {
        (total, false)
    };
    let travelled = if moving { travelled } else { total };
    for i in 0..segments {
        let (p, q) = (path[i], path[(i + 1) % n]);
        let len = p.distance(q);
        if s <= len || i == segments - 1 {
            let f = if len > 0.0 { (s / len).min(1.0) } else { 0.0 };
            let velocity = if moving && len > 0.0 {
                (q - p) * (speed / len)
            } else {
                Vec3::ZERO
            };
            return (p.lerp(q, f), velocity, travelled);
        }
        s -= len;
    }
    (path[0], Vec3::ZERO, travelled)
}
