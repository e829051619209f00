//! Pictures of the wind a person can read: a slice of the field with speed
//! as colour and direction as short streaks, drawn on the CPU from the
//! velocity read back from the GPU.

use glam::{Vec2, Vec3};

use crate::sim::wind::WindField;

/// Which plane to cut.
#[derive(Clone, Copy, Debug)]
pub enum Slice {
    /// The horizontal plane y = height (x right, z down the picture).
    Horizontal { height: f32 },
    /// The vertical plane z = depth (x right, y up).
    Vertical { depth: f32 },
}

/// Pixels per cell along the picture's width.
const PIXELS_PER_CELL: u32 = 8;
const STREAK_SPACING: u32 = 16;

/// Dark blue -> cyan -> yellow -> red over [0, 1].
fn ramp(t: f32) -> [u8; 3] {
    const STOPS: [[f32; 3]; 4] = [
        [0.05, 0.05, 0.35],
        [0.0, 0.75, 0.85],
        [0.95, 0.9, 0.1],
        [0.85, 0.1, 0.05],
    ];
    let t = t.clamp(0.0, 1.0) * 3.0;
    let i = (t.floor() as usize).min(2);
    let f = t - i as f32;
    let c: [f32; 3] = std::array::from_fn(|k| STOPS[i][k] * (1.0 - f) + STOPS[i + 1][k] * f);
    c.map(|v| (v * 255.0).round() as u8)
}

/// Renders `slice` of `field` as RGB8; returns (width, height, pixels).
/// Speed is scaled to `max_speed` (pass the field's maximum for contrast).
pub fn render(field: &WindField, slice: Slice, max_speed: f32) -> (u32, u32, Vec<u8>) {
    let g = field.grid;
    let size = g.size();
    let extent = match slice {
        Slice::Horizontal { .. } => Vec2::new(size.x, size.z),
        Slice::Vertical { .. } => Vec2::new(size.x, size.y),
    };
    let width = g.cells.x * PIXELS_PER_CELL;
    // Keep the aspect of the world, not of the cell counts.
    let height = ((width as f32 * extent.y / extent.x).round() as u32).max(1);
    let world = |px: f32, py: f32| -> Vec3 {
        let u = px / width as f32;
        let v = py / height as f32;
        match slice {
            Slice::Horizontal { height: y } => {
                g.origin + Vec3::new(u * size.x, y - g.origin.y, v * size.z)
            }
            Slice::Vertical { depth: z } => {
                g.origin + Vec3::new(u * size.x, (1.0 - v) * size.y, z - g.origin.z)
            }
        }
    };
    // In-plane direction of a velocity, in picture coordinates.
    let planar = |v: Vec3| match slice {
        Slice::Horizontal { .. } => Vec2::new(v.x, v.z),
        Slice::Vertical { .. } => Vec2::new(v.x, -v.y),
    };
    let scale = if max_speed > 0.0 { max_speed } else { 1.0 };
    let mut pixels = vec![0u8; (width * height * 3) as usize];
    for py in 0..height {
        for px in 0..width {
            let v = field.sample(world(px as f32 + 0.5, py as f32 + 0.5));
            let c = ramp(v.length() / scale);
            let i = ((py * width + px) * 3) as usize;
            pixels[i..i + 3].copy_from_slice(&c);
        }
    }
    // Streaks: a line along the flow from each grid point, longer when faster.
    let mut put = |x: i32, y: i32, c: [u8; 3]| {
        if x >= 0 && y >= 0 && (x as u32) < width && (y as u32) < height {
            let i = ((y as u32 * width + x as u32) * 3) as usize;
            pixels[i..i + 3].copy_from_slice(&c);
        }
    };
    let mut y = STREAK_SPACING / 2;
    while y < height {
        let mut x = STREAK_SPACING / 2;
        while x < width {
            let v = field.sample(world(x as f32, y as f32));
            let d = planar(v);
            let len = (d.length() / scale).min(1.0) * (STREAK_SPACING as f32 - 3.0);
            if let Some(dir) = d.try_normalize() {
                let steps = len.ceil() as i32;
                for s in 0..=steps {
                    let p = Vec2::new(x as f32, y as f32) + dir * s as f32;
                    put(p.x.round() as i32, p.y.round() as i32, [255, 255, 255]);
                }
                put(x as i32, y as i32, [20, 20, 20]);
            }
            x += STREAK_SPACING;
        }
        y += STREAK_SPACING;
    }
    (width, height, pixels)
}
