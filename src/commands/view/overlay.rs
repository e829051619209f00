//! What the viewer's overlay says, laid out by egui: frame rate, each
//! phase's GPU time, the blade counts, time and wind, and a debug view's
//! colour key. In a small window (under `FULL_FROM` points) it collapses
//! to two lines and a narrow key, so the frame stays in sight; the keys'
//! panel is then printed only. It takes no input (the keys act on the
//! viewer, not on it); `gpu::overlay` draws it.

use std::time::Instant;

use ash::vk;

use crate::error::Result;
use crate::frame::timing::Phase;
use crate::frame::FrameStats;
use crate::gpu::{Gpu, OverlayDraw, OverlayRenderer};
use crate::report::legend;
use crate::scene::ViewMode;

use super::script::KEYS;

/// What one frame's overlay shows.
pub struct Readout<'a> {
    pub scene: &'a str,
    pub fps: f64,
    /// The last frame's measurements.
    pub stats: &'a FrameStats,
    pub blades: usize,
    pub time: f64,
    pub time_scale: f64,
    pub paused: bool,
    pub lod: bool,
    pub view: ViewMode,
    /// The tessellation levels close to far, for the LOD view's key.
    pub lod_levels: [u32; 3],
    pub wind: String,
    /// The viewer's ball, where there is one.
    pub ball: Option<String>,
}

/// The smallest window (width, height, in points) the full panel is laid
/// out in: it is about 340 x 150 points, and a debug view's key 150 x 50.
pub const FULL_FROM: (f32, f32) = (560.0, 320.0);

pub struct Overlay {
    context: egui::Context,
    renderer: Option<OverlayRenderer>,
    pub shown: bool,
    pub keys_shown: bool,
    started: Instant,
}

/// A laid-out overlay ready to draw, and the textures to free after it.
pub struct Prepared {
    pub draw: OverlayDraw,
    free: Vec<egui::TextureId>,
}

impl Default for Overlay {
    /// Shown, without the keys; its renderer is made with the first frame
    /// (it needs the swapchain's format).
    fn default() -> Self {
        Self {
            context: egui::Context::default(),
            renderer: None,
            shown: true,
            keys_shown: false,
            started: Instant::now(),
        }
    }
}

/// The overlay's windows: the panel (compact in a small window), the
/// view's colour key outside the shaded view, and the keys when asked.
fn windows(ui: &mut egui::Ui, readout: &Readout, compact: bool, keys_shown: bool) {
    let context = ui.ctx().clone();
    let mut frame = egui::Frame::window(ui.style());
    if compact {
        // No drop shadow: in a small window it darkens much of
        // the frame beyond the panel.
        frame = frame.inner_margin(3.0).shadow(egui::Shadow::NONE);
    }
    egui::Window::new("meadow")
        .frame(frame)
        .title_bar(!compact)
        .anchor(egui::Align2::LEFT_TOP, [4.0, 4.0])
        .resizable(false)
        .collapsible(false)
        .show(&context, |ui| {
            if compact {
                compact_panel(ui, readout)
            } else {
                panel(ui, readout)
            }
        });
    if readout.view != ViewMode::Shaded {
        egui::Window::new("key")
            .frame(frame)
            .title_bar(false)
            .anchor(egui::Align2::RIGHT_BOTTOM, [-4.0, -4.0])
            .resizable(false)
            .collapsible(false)
            .show(&context, |ui| {
                view_key(ui, readout, if compact { 60.0 } else { 128.0 })
            });
    }
    if keys_shown && !compact {
        egui::Window::new("keys")
            .anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0])
            .resizable(false)
            .collapsible(false)
            .show(&context, |ui| {
                egui::Grid::new("keys").striped(true).show(ui, |ui| {
                    for (keys, what) in KEYS {
                        ui.strong(keys);
                        ui.label(what);
                        ui.end_row();
                    }
                })
            });
    }
}

impl Overlay {
    /// Lays the overlay out for a window of `extent` pixels at `scale`
    /// pixels per point, uploading what egui's textures changed (between
    /// frames). None while hidden.
    pub fn prepare(
        &mut self,
        gpu: &Gpu,
        format: vk::Format,
        extent: vk::Extent2D,
        scale: f32,
        readout: &Readout,
    ) -> Result<Option<Prepared>> {
        if !self.shown {
            return Ok(None);
        }
        if self.renderer.as_ref().is_none_or(|r| r.format != format) {
            self.renderer = None;
            self.renderer = Some(OverlayRenderer::new(gpu, format)?);
        }
        let mut input = egui::RawInput {
            screen_rect: Some(egui::Rect::from_min_size(
                egui::Pos2::ZERO,
                egui::vec2(extent.width as f32, extent.height as f32) / scale,
            )),
            time: Some(self.started.elapsed().as_secs_f64()),
            ..Default::default()
        };
        input
            .viewports
            .entry(egui::ViewportId::ROOT)
            .or_default()
            .native_pixels_per_point = Some(scale);
        let keys_shown = self.keys_shown;
        let points = egui::vec2(extent.width as f32, extent.height as f32) / scale;
        let compact = points.x < FULL_FROM.0 || points.y < FULL_FROM.1;
        let output = self
            .context
            .run_ui(input, |ui| windows(ui, readout, compact, keys_shown));
        let primitives = self
            .context
            .tessellate(output.shapes, output.pixels_per_point);
        // Taken out of egui's delta (which insists, when dropped, that it
        // was handled) before anything can fail: set now, freed after.
        let mut delta = output.textures_delta;
        let mut set: Vec<_> = std::mem::take(&mut delta.set)
            .into_iter()
            .flat_map(|(id, images)| images.into_iter().map(move |image| (id, image)))
            .collect();
        // egui's map has no order; its deltas of one texture keep theirs.
        set.sort_by_key(|(id, _)| *id);
        let free = std::mem::take(&mut delta.free).into_iter().collect();
        let renderer = self.renderer.as_mut().expect("made above");
        renderer.set_textures(&set)?;
        Ok(Some(Prepared {
            draw: OverlayDraw {
                primitives,
                pixels_per_point: output.pixels_per_point,
            },
            free,
        }))
    }

    /// The renderer and what to draw, for `FrameRecorder::present`.
    pub fn to_draw<'a>(
        &'a mut self,
        prepared: &'a Option<Prepared>,
    ) -> Option<(&'a mut OverlayRenderer, &'a OverlayDraw)> {
        match (self.renderer.as_mut(), prepared) {
            (Some(r), Some(p)) => Some((r, &p.draw)),
            _ => None,
        }
    }

    /// After the frame that drew `prepared` has completed.
    pub fn finish(&mut self, prepared: Option<Prepared>) -> Result<()> {
        match (self.renderer.as_mut(), prepared) {
            (Some(r), Some(p)) => r.free_textures(&p.free),
            _ => Ok(()),
        }
    }
}

fn panel(ui: &mut egui::Ui, r: &Readout) {
    ui.label(egui::RichText::new(r.scene).strong());
    let gpu = r
        .stats
        .timings
        .map(|t| format!(", GPU frame {:.1} ms", t.get(Phase::Frame)))
        .unwrap_or_default();
    ui.label(format!("{:.1} FPS{gpu}", r.fps));
    if let Some(t) = r.stats.timings {
        let phases = [
            (Phase::Wind, "wind"),
            (Phase::Grass, "grass"),
            (Phase::Cull, "cull"),
            (Phase::Shadow, "shadow"),
            (Phase::Color, "colour"),
        ]
        .map(|(p, name)| format!("{name} {:.1}", t.get(p)))
        .join("  ");
        ui.label(format!("ms: {phases}"));
    }
    let drawn = match r.stats.cull {
        Some(c) => format!(
            "blades {}: {} drawn, {} cast shadows",
            r.blades, c.in_view, c.shadow_casters
        ),
        None => format!("blades {}: all drawn", r.blades),
    };
    ui.label(drawn);
    if let Some(s) = r.stats.statistics {
        ui.label(format!(
            "segments {}, primitives {}",
            s.geometry_shader_invocations, s.geometry_shader_primitives
        ));
    }
    let paused = if r.paused { ", paused" } else { "" };
    ui.label(format!(
        "time {:.2} s at x{}{paused}; LOD {}; view {}",
        r.time,
        r.time_scale,
        if r.lod { "on" } else { "off" },
        view_name(r.view)
    ));
    ui.label(format!("wind: {}", r.wind));
    if let Some(ball) = &r.ball {
        ui.label(format!("ball: {ball}"));
    }
    ui.label("H: keys   O: hide this");
}

fn view_name(view: ViewMode) -> String {
    format!("{view:?}").to_lowercase()
}

/// The panel in a small window: two short lines.
fn compact_panel(ui: &mut egui::Ui, r: &Readout) {
    let small = |text: String| egui::RichText::new(text).small();
    let paused = if r.paused { ", paused" } else { "" };
    ui.label(small(format!(
        "{:.1} FPS  t {:.1} s{paused}  {}",
        r.fps,
        r.time,
        view_name(r.view)
    )));
    ui.label(small("H: keys (printed)  O: hide".into()));
}

/// A debug view's colour key, as the frames `render` writes stamp it: the
/// motion view's ramp `width` points long, the LOD view's three levels.
fn view_key(ui: &mut egui::Ui, r: &Readout, width: f32) {
    let colour = |c: [f32; 3]| {
        let [r, g, b] = legend::srgb(c);
        egui::Color32::from_rgb(r, g, b)
    };
    let small = |text: &str| egui::RichText::new(text).small();
    match r.view {
        ViewMode::Shaded => {}
        ViewMode::Motion => {
            ui.label(small("tip bend (rad)"));
            let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 8.0), egui::Sense::hover());
            let slices = width as usize;
            for i in 0..slices {
                let t = i as f32 / (slices - 1) as f32;
                let x = rect.left() + t * (width - 1.0);
                let slice = egui::Rect::from_min_max(
                    egui::pos2(x, rect.top()),
                    egui::pos2(x + 1.0, rect.bottom()),
                );
                let angle = legend::MOTION_FULL_SCALE * t;
                ui.painter()
                    .rect_filled(slice, 0.0, colour(legend::motion_color(angle)));
            }
            ui.horizontal(|ui| {
                ui.label(small("0"));
                ui.add_space(width - 36.0);
                ui.label(small(&format!("{}+", legend::MOTION_FULL_SCALE)));
            });
        }
        ViewMode::Lod => {
            ui.label(small("segments"));
            ui.horizontal(|ui| {
                for (c, level) in legend::LOD_COLORS.iter().zip(r.lod_levels) {
                    let (rect, _) =
                        ui.allocate_exact_size(egui::vec2(8.0, 8.0), egui::Sense::hover());
                    ui.painter().rect_filled(rect, 0.0, colour(*c));
                    ui.label(small(&level.to_string()));
                }
            });
        }
    }
}
