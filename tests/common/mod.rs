//! Shared by the GPU tests: every test opens the GPU with the Khronos
//! validation layer (core + synchronization checks) and fails on any error
//! it reports, leaks at device destruction included.

#![allow(dead_code)]

pub mod binary;
pub mod cover;
pub mod cpu_sim;
pub mod reflect;
pub mod scene_property;
pub mod sim;
pub mod wind_scenes;

use meadow::commands::render::{Animation, RenderRequest};
use meadow::frame::Frame;
use meadow::gpu::{Gpu, GpuOptions, ValidationOptions};
use meadow::model::Blade;
use meadow::render::ViewMode;
use meadow::scene::Scene;

/// The wind grid of the tests whose claim does not depend on the wind's
/// resolution: half the paper's 60 x 20 x 60 cells along each axis, every
/// kernel of the step and every level of its multigrid still run, at
/// about an eighth of the steps' cost on lavapipe.
pub const COARSE_WIND_CELLS: [u32; 3] = [30, 10, 30];

/// The mean of a series and its spread (standard deviation) about it.
pub fn mean_spread(v: &[f64]) -> (f64, f64) {
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let spread = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64).sqrt();
    (mean, spread)
}

pub fn strict_gpu() -> Gpu {
    strict_gpu_with(None)
}

/// As `strict_gpu`, one storage binding reaching at most `storage_range`
/// bytes: the kernels that run in batches (src/gpu/batches.rs) run in
/// several on a few thousand blades.
pub fn strict_gpu_with(storage_range: Option<u32>) -> Gpu {
    // Keep the test log readable; messages are still counted and asserted.
    std::env::set_var("MEADOW_QUIET_VALIDATION", "1");
    let options = GpuOptions {
        validation: ValidationOptions::strict(),
        device_name: std::env::var("MEADOW_TEST_DEVICE").ok(),
        storage_range,
        ..Default::default()
    };
    Gpu::new(&options).unwrap_or_else(|e| {
        panic!("the GPU tests need Vulkan with the validation layer (scripts/ensure-vulkan): {e}")
    })
}

/// Tears the GPU down and asserts validation reported no error at all.
pub fn finish(gpu: Gpu) {
    let report = gpu.destroy();
    assert!(report.enabled, "validation was not enabled");
    if report.errors > 0 {
        for m in &report.messages {
            eprintln!("{} x{} {}: {}", m.severity, m.count, m.id, m.first_text);
        }
    }
    assert_eq!(
        report.errors, 0,
        "validation errors: {:#?}",
        report.messages
    );
}

/// A render request as the tests make them: strict validation (messages
/// counted, not echoed), shaded, 4x MSAA asked, `frames` frames at `fps`
/// from t = 0, every one written, a GIF when there are several.
pub fn strict_request(
    scene: Scene,
    width: u32,
    height: u32,
    frames: u32,
    fps: f32,
) -> RenderRequest {
    std::env::set_var("MEADOW_QUIET_VALIDATION", "1");
    RenderRequest {
        scene,
        width,
        height,
        msaa: 4,
        view: ViewMode::Shaded,
        animation: Animation {
            frames,
            fps,
            start: 0.0,
        },
        every: 1,
        gif: true,
        video: None,
        overwrite: false,
        light_waves: false,
        gpu: GpuOptions {
            validation: ValidationOptions::strict(),
            ..Default::default()
        },
    }
}

pub fn render(
    gpu: &Gpu,
    scene: &Scene,
    blades: &[Blade],
    width: u32,
    height: u32,
    view: ViewMode,
) -> Frame {
    meadow::frame::render_blades(gpu, scene, blades, (width, height), 4, view)
        .unwrap_or_else(|e| panic!("render failed: {e}"))
        .0
}

/// The xyz of a vec4 as the GLSL side stores positions and widths.
pub fn to_vec3(v: [f32; 3]) -> glam::Vec3 {
    glam::Vec3::from(v)
}

pub fn pixel(frame: &Frame, x: u32, y: u32) -> [u8; 3] {
    let i = ((y * frame.width + x) * 4) as usize;
    [frame.rgba[i], frame.rgba[i + 1], frame.rgba[i + 2]]
}

/// Pixel (x, y) where a world point lands in a `w` x `h` frame of `scene`.
pub fn project(scene: &Scene, p: glam::Vec3, w: u32, h: u32) -> (f32, f32) {
    let clip = meadow::render::frame_uniforms::view_projection(scene, w as f32 / h as f32, 0.0)
        * p.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    (
        (ndc.x * 0.5 + 0.5) * w as f32,
        (ndc.y * 0.5 + 0.5) * h as f32,
    )
}

/// Mean of each channel over a rectangle.
pub fn mean_rgb(frame: &Frame, x0: u32, y0: u32, x1: u32, y1: u32) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut n = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            let p = pixel(frame, x, y);
            for c in 0..3 {
                sum[c] += p[c] as f64;
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

/// The FLIP error of each pixel between two frames of the same size.
pub fn flip_errors(a: &Frame, b: &Frame) -> Vec<f32> {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let rgb = |f: &Frame| -> Vec<u8> {
        f.rgba
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect()
    };
    let image = |f: &Frame| nv_flip::FlipImageRgb8::with_data(f.width, f.height, &rgb(f));
    nv_flip::flip(image(a), image(b), nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec()
}

/// The mean FLIP error between two picture files of the same size.
pub fn mean_flip_of_files(a: &std::path::Path, b: &std::path::Path) -> f32 {
    let a = image::open(a)
        .unwrap_or_else(|e| panic!("{}: {e}", a.display()))
        .to_rgb8();
    let b = image::open(b)
        .unwrap_or_else(|e| panic!("{}: {e}", b.display()))
        .to_rgb8();
    assert_eq!(a.dimensions(), b.dimensions());
    let (w, h) = a.dimensions();
    let a = nv_flip::FlipImageRgb8::with_data(w, h, a.as_raw());
    let b = nv_flip::FlipImageRgb8::with_data(w, h, b.as_raw());
    let error = nv_flip::flip(a, b, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec();
    error.iter().sum::<f32>() / error.len() as f32
}
