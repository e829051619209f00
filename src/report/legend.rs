//! The key of a debug view, stamped into the frame's bottom-right corner
//! before it is written: the motion view's colour ramp with the bend it
//! stands for in radians, the LOD view's three colours with their segment
//! counts. Text in the public-domain 8 x 8 bitmap font of `font8x8`.

use crate::frame::Frame;
use crate::scene::ViewMode;

/// The motion view's ramp (glsl/blade/blade.frag, VIEW_MOTION): albedo
/// from `MOTION_AT_REST` at 0 rad to `MOTION_FULL` at `MOTION_FULL_SCALE`
/// rad of the tip edge's angle from rest, linear RGB. Mirrors the shader.
pub const MOTION_AT_REST: [f32; 3] = [0.05, 0.15, 0.6];
pub const MOTION_FULL: [f32; 3] = [0.9, 0.1, 0.05];
pub const MOTION_FULL_SCALE: f32 = 0.6;

/// The LOD view's colours by tessellation level, close to far
/// (`lod_color` in glsl/blade/blade.frag), linear RGB.
pub const LOD_COLORS: [[f32; 3]; 3] = [[0.85, 0.10, 0.08], [0.95, 0.75, 0.05], [0.10, 0.35, 0.90]];

/// Linear RGB to the sRGB bytes the frame holds.
pub fn srgb(c: [f32; 3]) -> [u8; 3] {
    c.map(|v| {
        let v = v.clamp(0.0, 1.0);
        let s = if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    })
}

/// The motion view's albedo at `angle` radians, as the shader mixes it.
pub fn motion_color(angle: f32) -> [f32; 3] {
    let t = (angle / MOTION_FULL_SCALE).clamp(0.0, 1.0);
    std::array::from_fn(|k| MOTION_AT_REST[k] * (1.0 - t) + MOTION_FULL[k] * t)
}

struct Canvas<'a> {
    frame: &'a mut Frame,
}

impl Canvas<'_> {
    fn put(&mut self, x: i32, y: i32, c: [u8; 3]) {
        let (w, h) = (self.frame.width as i32, self.frame.height as i32);
        if (0..w).contains(&x) && (0..h).contains(&y) {
            let i = ((y * w + x) * 4) as usize;
            self.frame.rgba[i..i + 3].copy_from_slice(&c);
        }
    }

    fn fill(&mut self, x0: i32, y0: i32, w: i32, h: i32, c: [u8; 3]) {
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                self.put(x, y, c);
            }
        }
    }

    /// `text` in 8 x 8 glyphs with its top-left at (x, y).
    fn text(&mut self, x: i32, y: i32, text: &str, c: [u8; 3]) {
        for (n, ch) in text.chars().enumerate() {
            let glyph = font8x8::legacy::BASIC_LEGACY[(ch as usize).min(127)];
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..8 {
                    if bits >> col & 1 == 1 {
                        self.put(x + 8 * n as i32 + col, y + row as i32, c);
                    }
                }
            }
        }
    }
}

const INK: [u8; 3] = [240, 240, 240];
const PANEL: [u8; 3] = [20, 20, 24];

/// The key's width and height in pixels for `view` (None: no key).
fn size(view: ViewMode) -> Option<(i32, i32)> {
    match view {
        ViewMode::Shaded => None,
        ViewMode::Motion => Some((8 * 17 + 8, 44)),
        ViewMode::Lod => Some((8 * 14 + 8, 40)),
    }
}

/// The smallest frame (width, height) the key of `view` is stamped into:
/// three keys wide and four high; in a smaller one (a preview) the key
/// would hide much of the picture. None: the view has no key.
pub fn smallest_frame(view: ViewMode) -> Option<(u32, u32)> {
    size(view).map(|(w, h)| (3 * w as u32, 4 * h as u32))
}

/// What the key of `view` says, in words: for a frame too small to hold
/// it, and for the viewer's terminal. None: the view has no key.
pub fn words(view: ViewMode, levels: [u32; 3]) -> Option<String> {
    match view {
        ViewMode::Shaded => None,
        ViewMode::Motion => Some(format!(
            "colour is the tip's bend from rest, blue at 0 rad to red at {MOTION_FULL_SCALE} rad and more"
        )),
        ViewMode::Lod => Some(format!(
            "colour is the blade's tessellation, red {} segments (close), yellow {}, blue {} (far)",
            levels[0], levels[1], levels[2]
        )),
    }
}

/// Why a `width` x `height` frame of `view` goes without its key, with
/// the key in words (None: it has its key, or the view has none).
pub fn left_out(view: ViewMode, levels: [u32; 3], width: u32, height: u32) -> Option<String> {
    let (w, h) = smallest_frame(view)?;
    if width >= w && height >= h {
        return None;
    }
    let name = format!("{view:?}").to_lowercase();
    Some(format!(
        "the {name} view's key is left out of {width} x {height} frames (it is stamped from {w} x {h} up): {}",
        words(view, levels)?
    ))
}

/// Stamps the key of `view` into the bottom-right corner of `frame`; the
/// shaded view has none, and a frame smaller than `smallest_frame` (a
/// preview, where the key would hide much of it) is left alone: `left_out`
/// says so in words.
pub fn stamp(frame: &mut Frame, view: ViewMode, levels: [u32; 3]) {
    let Some((w, h)) = size(view) else {
        return;
    };
    if left_out(view, levels, frame.width, frame.height).is_some() {
        return;
    }
    let (x0, y0) = (frame.width as i32 - w - 4, frame.height as i32 - h - 4);
    let mut canvas = Canvas { frame };
    canvas.fill(x0, y0, w, h, PANEL);
    match view {
        ViewMode::Shaded => {}
        ViewMode::Motion => {
            canvas.text(x0 + 4, y0 + 3, "tip bend (rad)", INK);
            let bar = w - 8;
            for i in 0..bar {
                let angle = MOTION_FULL_SCALE * i as f32 / (bar - 1) as f32;
                canvas.fill(x0 + 4 + i, y0 + 14, 1, 12, srgb(motion_color(angle)));
            }
            canvas.text(x0 + 4, y0 + 30, "0", INK);
            canvas.text(x0 + 4 + bar / 2 - 12, y0 + 30, "0.3", INK);
            canvas.text(x0 + w - 4 - 32, y0 + 30, "0.6+", INK);
        }
        ViewMode::Lod => {
            canvas.text(x0 + 4, y0 + 3, "segments", INK);
            for (k, (colour, level)) in LOD_COLORS.iter().zip(levels).enumerate() {
                let x = x0 + 4 + 40 * k as i32;
                canvas.fill(x, y0 + 16, 10, 10, srgb(*colour));
                canvas.text(x + 12, y0 + 18, &level.to_string(), INK);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blank(width: u32, height: u32) -> Frame {
        Frame {
            width,
            height,
            rgba: vec![128; (width * height * 4) as usize],
            statistics: None,
            shadow_statistics: None,
            timings: None,
            cull: None,
        }
    }

    #[test]
    fn the_motion_key_runs_from_the_rest_colour_to_the_full_one() {
        let mut frame = blank(640, 360);
        stamp(&mut frame, ViewMode::Motion, [20, 10, 3]);
        let at = |x: u32, y: u32| {
            let i = ((y * frame.width + x) * 4) as usize;
            [frame.rgba[i], frame.rgba[i + 1], frame.rgba[i + 2]]
        };
        let (w, h) = size(ViewMode::Motion).unwrap();
        let (x0, y0) = (640 - w as u32 - 4, 360 - h as u32 - 4);
        assert_eq!(at(x0 + 4, y0 + 20), srgb(MOTION_AT_REST));
        assert_eq!(at(x0 + w as u32 - 5, y0 + 20), srgb(MOTION_FULL));
        // Text in the ink colour, and the rest of the frame untouched.
        assert!((0..w as u32).any(|x| at(x0 + x, y0 + 6) == INK));
        assert_eq!(at(10, 10), [128; 3]);
    }

    #[test]
    fn the_shaded_view_and_tiny_frames_get_no_key() {
        for (view, (w, h)) in [
            (ViewMode::Shaded, (640, 360)),
            (ViewMode::Motion, (320, 180)),
        ] {
            let mut frame = blank(w, h);
            stamp(&mut frame, view, [20, 10, 3]);
            assert!(frame.rgba.iter().all(|&v| v == 128), "{view:?} {w}x{h}");
        }
        // A key left out is said in words; one stamped is not.
        let said = left_out(ViewMode::Motion, [20, 10, 3], 320, 180).unwrap();
        assert!(
            said.starts_with("the motion view's key is left out of 320 x 180 frames (it is stamped from 432 x 176 up): colour is the tip's bend"),
            "{said}"
        );
        let said = left_out(ViewMode::Lod, [20, 10, 3], 200, 500).unwrap();
        assert!(
            said.contains("red 20 segments (close), yellow 10, blue 3 (far)"),
            "{said}"
        );
        assert_eq!(left_out(ViewMode::Motion, [20, 10, 3], 432, 176), None);
        assert_eq!(left_out(ViewMode::Shaded, [20, 10, 3], 32, 18), None);
        let mut frame = blank(432, 176);
        stamp(&mut frame, ViewMode::Motion, [20, 10, 3]);
        assert!(
            frame.rgba.iter().any(|&v| v != 128),
            "432 x 176 holds the key"
        );
    }
}
