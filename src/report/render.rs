//! What `meadow render` reports: report.json's content, and the summary
//! the command prints.

use std::path::Path;

use crate::analysis::light_waves::LightWaves;
use crate::frame::timing::TimingSummary;
use crate::frame::{Animation, CullCounts};
use crate::gpu::query::PipelineStatistics;
use crate::gpu::{DeviceMemory, ValidationReport};
use crate::model::grass::CapCounts;
use crate::model::multigrid::SolveCounts;
use crate::model::wind::Coupling;
use crate::scene::{Camera, ViewMode};

/// What `report.json` holds.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RenderReport {
    /// The process's command line, to run it again.
    pub command_line: Vec<String>,
    /// The scene as rendered (overrides applied, `[render]` set to this
    /// run's settings), written beside this report.
    pub scene_file: String,
    /// Side of the shadow map in texels (0: no shadows).
    pub shadow_map: u32,
    pub camera: Camera,
    pub scene: String,
    pub seed: u64,
    pub device: String,
    pub device_type: String,
    pub driver: String,
    pub api_version: String,
    /// The device memory the run's allocations held at the end and at
    /// most (`gpu::DeviceMemory`).
    pub device_memory: DeviceMemory,
    pub msaa_requested: u32,
    pub msaa_used: u32,
    /// Blades drawn, and those the patches planted but the obstacles
    /// left out (their roots inside one).
    pub blades: usize,
    pub blades_under_obstacles: usize,
    /// The last frame's blades by what happened to them.
    pub blade_counts: BladeCounts,
    /// With `[grass.cover]`: the largest distance (m) a cover blade's tip
    /// moved from one drawn frame to the next over the whole render
    /// (blades posed in both), over every posed blade and over those posed
    /// quasi-statically (the far field): how much the far field pops.
    /// Absent without a cover.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cover_largest_tip_jump_m: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cover_largest_far_tip_jump_m: Option<f32>,
    pub width: u32,
    pub height: u32,
    pub lod: bool,
    pub tess_levels: [u32; 3],
    pub lod_distances: [f32; 2],
    pub view: ViewMode,
    pub animation: Animation,
    /// Whether the grass slows the wind (one-way: the paper's).
    pub coupling: Coupling,
    /// The simulation step (s) and its symplectic Euler substeps.
    pub sim_dt: f32,
    pub substeps: u32,
    /// Simulation steps run in all.
    pub sim_steps: u64,
    /// Blade-steps that ended with an angle at its cap (motion the model
    /// could not follow; docs/physics.md), and their share.
    pub angle_caps: CapCounts,
    pub cap_fraction: f64,
    /// The wind's multigrid pressure solves over the run: steps, V-cycles
    /// per step (median, most, mean) and the wind step's dispatches that
    /// ran workgroups at the median and that it records (null with the
    /// Jacobi solver).
    pub wind_solve: Option<SolveCounts>,
    /// Frames asked for (after --every) and the files written, in order.
    pub frames_planned: u32,
    pub frames: Vec<String>,
    /// The animated GIF of the written frames, when there are several.
    pub gif: Option<String>,
    /// The video of the written frames (`--video`), as its path was given.
    pub video: Option<String>,
    /// Stopped early (Ctrl-C): `frames` says how far it got, and every
    /// file listed is complete.
    pub interrupted: bool,
    /// What the scene will do less than it says (e.g. a wind source outside
    /// the grid), one line each.
    pub warnings: Vec<String>,
    /// The colour pass's grass draw, last frame.
    pub pipeline_statistics: Option<PipelineStatistics>,
    /// The shadow pass, last frame (null without shadows or support).
    pub shadow_pipeline_statistics: Option<PipelineStatistics>,
    /// Whether a compute pass culled the blades each frame, and of the
    /// last frame's blades how many each pass drew (null with culling off:
    /// every blade in both).
    pub cull: bool,
    pub cull_counts: Option<CullCounts>,
    /// Per-phase GPU time (median, p95), wall-clock frame time and FPS.
    pub timing: TimingSummary,
    /// With `--light-waves`: whether the shaded picture shows the blades'
    /// motion (`analysis::light_waves`); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub light_waves: Option<LightWaves>,
    /// Wall-clock seconds of the whole job (GPU start-up to teardown).
    pub wall_seconds: f64,
    pub validation: ValidationReport,
}

/// The last frame's blades by what happened to them: made by the cover's
/// tile pass, stepped by the paper's dynamics (the patches' and the
/// cover's tiles reaching within its `simulate_radius`), posed
/// quasi-statically in the wind (the cover's the frame may draw beyond
/// those tiles) or left in their rest shape (the cover's it cannot draw),
/// in view (with culling; else every blade) and drawn by the colour pass.
/// The cover's drawable blades of the simulated tiles take their state:
/// generated - at_rest - quasi_static of them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct BladeCounts {
    pub generated: u64,
    pub simulated: u64,
    pub quasi_static: u64,
    pub at_rest: u64,
    pub in_view: u64,
    pub drawn: u64,
}

/// What `meadow render` prints when it is done: the device and settings,
/// the grass draw's counters, validation, the per-phase timing table, the
/// simulated time and the files written under `out`.
pub fn summary(report: &RenderReport, out: &Path) -> String {
    let under = match report.blades_under_obstacles {
        0 => String::new(),
        n => format!("; {n} more planted, left out under obstacles"),
    };
    let mut text = format!(
        "rendered {} ({} blades{under}, {}x{}, MSAA {}x of {}x asked, LOD {}) on {} [{}] in {:.1} s\n",
        report.scene,
        report.blades,
        report.width,
        report.height,
        report.msaa_used,
        report.msaa_requested,
        if report.lod { "on" } else { "off" },
        report.device,
        report.device_type,
        report.wall_seconds
    );
    text += &draw_lines(report);
    text += &cover_lines(report);
    if let Some(w) = &report.light_waves {
        text += &light_waves_line(w);
    }
    if report.validation.enabled {
        text += &format!(
            "validation: {} errors, {} warnings\n",
            report.validation.errors, report.validation.warnings
        );
    }
    text += &super::timing::table(&report.timing);
    text += &format!(
        "simulated {:.2} s in {} steps of {:.4} s ({} substeps each), {} coupling\n",
        report.sim_steps as f64 * report.sim_dt as f64,
        report.sim_steps,
        report.sim_dt,
        report.substeps,
        report.coupling.name()
    );
    if report.angle_caps.blade_steps > 0 {
        text += &format!(
            "blade-steps at an angle cap: {:.3}% ({} of {})\n",
            100.0 * report.cap_fraction,
            report.angle_caps.at_cap,
            report.angle_caps.blade_steps
        );
    }
    text += &written_lines(report, out);
    text
}

/// The draws' counters: the grass's and the shadow pass's, the GPU memory,
/// what culling left.
fn draw_lines(report: &RenderReport) -> String {
    let mut text = String::new();
    if let Some(s) = &report.pipeline_statistics {
        text += &format!(
            "grass: {} patches, {} tessellation-evaluation invocations, {} geometry-shader invocations (segments), {} primitives\n",
            s.tessellation_control_patches,
            s.tessellation_evaluation_invocations,
            s.geometry_shader_invocations,
            s.geometry_shader_primitives
        );
    }
    if let Some(s) = &report.shadow_pipeline_statistics {
        text += &format!(
            "shadow pass: {} patches, {} segments, {} primitives\n",
            s.tessellation_control_patches,
            s.geometry_shader_invocations,
            s.geometry_shader_primitives
        );
    }
    text += &format!(
        "GPU memory: {:.1} MiB allocated at the end, {:.1} MiB at most\n",
        mib(report.device_memory.allocated_bytes),
        mib(report.device_memory.peak_bytes)
    );
    match &report.cull_counts {
        Some(c) => {
            text += &format!(
            "culling: {} of {} blades left by distance thinning, {} of them not edge-on to the camera, {} hidden by the previous frame's depth, {} in view, {} shadow casters, {} casters whose shadow that depth hides\n",
            c.thinned_to, c.blades, c.face_camera, c.occluded, c.in_view, c.shadow_casters, c.casters_occluded
        )
        }
        None => text += "culling: off (every blade drawn in both passes)\n",
    }
    text
}

/// The cover's blades and its largest tip moves, where there is one.
fn cover_lines(report: &RenderReport) -> String {
    let mut text = String::new();
    let b = &report.blade_counts;
    if b.generated > 0 {
        text += &format!(
            "cover: {} blades made around the camera each frame: {} posed from the paper's dynamics, {} quasi-statically in the wind (those the frame may draw), {} at rest; {} blades simulated\n",
            b.generated,
            b.generated - b.quasi_static - b.at_rest,
            b.quasi_static,
            b.at_rest,
            b.simulated
        );
    }
    if let (Some(all), Some(far)) = (
        report.cover_largest_tip_jump_m,
        report.cover_largest_far_tip_jump_m,
    ) {
        text += &format!(
            "cover: a tip moved at most {:.3} m between frames ({:.3} m posed quasi-statically)\n",
            all, far
        );
    }
    text
}

/// The files written under `out`.
fn written_lines(report: &RenderReport, out: &Path) -> String {
    let mut text = String::new();
    match report.frames.as_slice() {
        [one] => text += &format!("wrote {}\n", out.join(one).display()),
        [first, .., last] => {
            text += &format!(
                "wrote {} frames, {} .. {}\n",
                report.frames.len(),
                out.join(first).display(),
                out.join(last).display()
            )
        }
        [] => {}
    }
    if let Some(gif) = &report.gif {
        text += &format!("wrote {}\n", out.join(gif).display());
    }
    if let Some(video) = &report.video {
        text += &format!("wrote {video}\n");
    }
    text
}

fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1u64 << 20) as f64
}

/// The waves of light in one line.
pub fn light_waves_line(w: &LightWaves) -> String {
    match (w.modulation_median, w.correlation_abs_median) {
        (Some(modulation), Some(r)) => format!(
            "light waves: over {} frames ({:.2} s), {} of {} blocks of {} x {} pixels are grass; \
             their luminance varies by {:.2}% of its mean (median; quartiles {:.2}-{:.2}%) and \
             follows the blades' displacement with median |r| {:.2}\n",
            w.frames,
            w.seconds,
            w.blocks,
            w.blocks_in_frame,
            w.block_pixels,
            w.block_pixels,
            100.0 * modulation,
            100.0 * w.modulation_p25.unwrap_or(modulation),
            100.0 * w.modulation_p75.unwrap_or(modulation),
            r
        ),
        _ => format!(
            "light waves: none of the {} blocks is grass in every frame (blades covering {:.0}% or more)\n",
            w.blocks_in_frame,
            100.0 * w.least_grass_share
        ),
    }
}
