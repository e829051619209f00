//! `meadow bench-grass`: GPU time of the grass step alone (timestamp
//! queries around each dispatch) at several blade counts, the figures the
//! paper gives for its grass step (8.5 / 16.9 / 25.8 / 33.5 ms for 50K /
//! 100K / 150K / 200K blades on a GTX 670). The wind is solved for a while
//! first so that the blades move, and then held: only the grass is timed.

use crate::commands::on_gpu;
use crate::error::{Error, Result};
use crate::frame::timing::median_p95;
use crate::frame::BladeBuffer;
use crate::gpu::query::TimestampQueries;
use crate::gpu::{Access, Commands, Gpu, GpuOptions, ValidationReport};
use crate::scene::{field, Scene, MAX_BLADES};
use crate::sim::canopy;
use crate::simulate::{GrassPass, WindPass};

/// The paper's grass-step times (ms) on a GTX 670, by blade count.
pub const PAPER_GRASS_MS: [(usize, f64); 4] = [
    (50_000, 8.5),
    (100_000, 16.9),
    (150_000, 25.8),
    (200_000, 33.5),
];

/// Wind steps run before timing, so that the grass meets a developed field.
const WIND_WARMUP_STEPS: u32 = 30;

#[derive(Clone, Debug, serde::Serialize)]
pub struct GrassBenchRow {
    pub blades: usize,
    pub substeps: u32,
    /// Timed steps (after `warmup` untimed ones).
    pub steps: u32,
    pub warmup: u32,
    /// GPU ms per grass step; None without timestamps.
    pub step_ms_median: Option<f64>,
    pub step_ms_p95: Option<f64>,
    /// The paper's figure for this count, where it gives one.
    pub paper_ms: Option<f64>,
    /// Bytes the step must read and write at least
    /// (`grass_pass::bytes_per_step`).
    pub bytes_per_step: u64,
    /// Those bytes at the copy bandwidth measured in the same run (ms):
    /// the memory-bandwidth floor.
    pub floor_ms: Option<f64>,
    /// The median step over the floor.
    pub over_floor: Option<f64>,
}

/// The device's copy bandwidth: one buffer copied into another with
/// vkCmdCopyBuffer, timed by timestamps.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CopyBandwidth {
    /// Bytes copied each time (read once and written once).
    pub bytes: u64,
    pub copies: u32,
    /// Bytes read plus written per second over the median copy (GB/s,
    /// 1e9 bytes).
    pub gb_per_s: f64,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct GrassBench {
    pub scene: String,
    pub device: String,
    pub device_type: String,
    pub rows: Vec<GrassBenchRow>,
    /// None where the device has no timestamps.
    pub copy_bandwidth: Option<CopyBandwidth>,
    pub validation: ValidationReport,
}

/// Times `steps` grass steps (after `warmup`) of `scene` at each count.
pub fn bench_grass(
    scene: &Scene,
    counts: &[usize],
    steps: u32,
    warmup: u32,
    options: &GpuOptions,
) -> Result<GrassBench> {
    if counts.is_empty() || counts.iter().any(|&n| n == 0 || n > MAX_BLADES) {
        return Err(Error::InvalidInput(format!(
            "blade counts {counts:?} are not allowed, use 1..={MAX_BLADES} each"
        )));
    }
    if !(1..=10_000).contains(&steps) || warmup > 10_000 {
        return Err(Error::InvalidInput(format!(
            "--steps {steps} / --warmup {warmup} are not allowed, use 1..=10000 and 0..=10000"
        )));
    }
    scene.wind_grid()?;
    scene.grass.dynamics.validate()?;
    let ((rows, copy_bandwidth, info), validation) = on_gpu(options, |gpu| {
        let copy = copy_bandwidth(gpu)?;
        let rows = counts
            .iter()
            .map(|&n| bench_count(gpu, scene, n, steps, warmup, copy.as_ref()))
            .collect::<Result<Vec<_>>>()?;
        Ok((rows, copy, gpu.info().clone()))
    })?;
    let bench = GrassBench {
        scene: scene.name.clone(),
        device: info.name,
        device_type: info.device_type,
        rows,
        copy_bandwidth,
        validation,
    };
    bench.validation.check()?;
    Ok(bench)
}

fn bench_count(
    gpu: &Gpu,
    scene: &Scene,
    count: usize,
    steps: u32,
    warmup: u32,
    copy: Option<&CopyBandwidth>,
) -> Result<GrassBenchRow> {
    let mut scene = scene.clone();
    scene.set_blade_count(count)?;
    let blades = scene.field()?;
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed)?;
    gpu.check_fits(
        &format!("{count} blades"),
        crate::simulate::grass_pass::device_bytes(count),
    )?;

    let grid = scene.wind_grid()?;
    let dt = scene.wind.dt;
    let commands = Commands::new(gpu, "grass bench commands")?;
    let wind = WindPass::new(
        gpu,
        &commands,
        grid,
        &scene.wind_settings(),
        canopy::unit(&dynamic),
    )?;
    let rec = commands.begin()?;
    for i in 0..WIND_WARMUP_STEPS {
        wind.record_step(&rec, i as f32 * dt, dt);
    }
    rec.submit_and_wait("wind warm-up")?;
    let vertices = BladeBuffer::uninitialised(gpu, "grass bench vertices", count)?;
    let grass = GrassPass::new(
        gpu,
        &commands,
        &dynamic,
        vertices.buffer(),
        &wind.grass_input(),
        &scene.colliders,
        dt,
    )?;
    let timestamps = TimestampQueries::new(gpu, steps, "grass step timestamps")?;

    let rec = commands.begin()?;
    let end_time = |step: u32| crate::sim::contact::step_end_time(step as u64, dt);
    for n in 0..warmup {
        grass.record_step(&rec, 0, end_time(n));
    }
    if let Some(t) = &timestamps {
        t.reset(&rec);
    }
    for n in 0..steps {
        if let Some(t) = &timestamps {
            t.stamp(&rec, n, false);
        }
        grass.record_step(&rec, 0, end_time(warmup + n));
        if let Some(t) = &timestamps {
            t.stamp(&rec, n, true);
        }
    }
    rec.submit_and_wait("grass steps")?;
    let times = match &timestamps {
        Some(t) => t.read_ms(steps)?,
        None => Vec::new(),
    };
    let timing = median_p95(&times);
    let bytes_per_step = crate::simulate::grass_pass::bytes_per_step(count);
    let floor_ms = copy.map(|c| bytes_per_step as f64 / (c.gb_per_s * 1e9) * 1e3);
    Ok(GrassBenchRow {
        bytes_per_step,
        floor_ms,
        over_floor: floor_ms
            .zip(timing)
            .filter(|(f, _)| *f > 0.0)
            .map(|(f, t)| t.0 / f),
        blades: count,
        substeps: grass.substeps(),
        steps,
        warmup,
        step_ms_median: timing.map(|t| t.0),
        step_ms_p95: timing.map(|t| t.1),
        paper_ms: PAPER_GRASS_MS
            .iter()
            .find(|(n, _)| *n == count)
            .map(|(_, ms)| *ms),
    })
}

/// Bytes copied to measure the bandwidth: large enough to leave every
/// cache, small enough for any device meadow runs on.
const COPY_BYTES: u64 = 256 << 20;
const COPIES: u32 = 7;

/// Times `COPIES` copies of a `COPY_BYTES` buffer into another: the
/// bandwidth the grass step's floor is measured against, on the same
/// device in the same run. None without timestamps.
fn copy_bandwidth(gpu: &Gpu) -> Result<Option<CopyBandwidth>> {
    use ash::vk;
    gpu.check_fits("the bandwidth copy", 2 * COPY_BYTES)?;
    let Some(timestamps) = TimestampQueries::new(gpu, COPIES, "bandwidth copy timestamps")? else {
        return Ok(None);
    };
    let buffer = |name| {
        crate::gpu::Buffer::new(
            gpu,
            name,
            COPY_BYTES,
            vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST,
            crate::gpu::MemoryLocation::GpuOnly,
        )
    };
    let (src, dst) = (
        buffer("bandwidth copy source")?,
        buffer("bandwidth copy target")?,
    );
    let commands = Commands::new(gpu, "bandwidth copy commands")?;
    let rec = commands.begin()?;
    // Written once first, so no page is touched for the first time while
    // timed.
    rec.fill_buffer(&src, 0);
    rec.fill_buffer(&dst, 0);
    timestamps.reset(&rec);
    for n in 0..COPIES {
        rec.barrier(
            Access::TRANSFER_WRITE,
            Access::COPY_READ.and(Access::COPY_WRITE),
        );
        timestamps.stamp(&rec, n, false);
        rec.copy_buffer(&src, &dst, COPY_BYTES);
        timestamps.stamp(&rec, n, true);
    }
    rec.submit_and_wait("bandwidth copies")?;
    let times = timestamps.read_ms(COPIES)?;
    Ok(median_p95(&times)
        .filter(|(median, _)| *median > 0.0)
        .map(|(median, _)| CopyBandwidth {
            bytes: COPY_BYTES,
            copies: COPIES,
            gb_per_s: 2.0 * COPY_BYTES as f64 / (median * 1e-3) / 1e9,
        }))
}

/// "50k" -> 50000, "1.5m" -> 1500000, "1200" -> 1200.
pub fn parse_count(text: &str) -> Result<usize> {
    let t = text.trim().to_ascii_lowercase();
    let (digits, scale) = match t.strip_suffix('k') {
        Some(d) => (d, 1e3),
        None => match t.strip_suffix('m') {
            Some(d) => (d, 1e6),
            None => (t.as_str(), 1.0),
        },
    };
    digits
        .parse::<f64>()
        .ok()
        .map(|v| v * scale)
        .filter(|v| v.is_finite() && *v >= 1.0 && v.fract() == 0.0 && *v <= MAX_BLADES as f64)
        .map(|v| v as usize)
        .ok_or_else(|| {
            Error::InvalidInput(format!(
                "blade count {text:?} is not a count, write e.g. 50k, 1.5m or 1200 (at most {MAX_BLADES})"
            ))
        })
}

#[cfg(test)]
mod tests {
    use super::parse_count;

    #[test]
    fn counts_parse_with_suffixes() {
        assert_eq!(parse_count("50k").unwrap(), 50_000);
        assert_eq!(parse_count("1.5M").unwrap(), 1_500_000);
        assert_eq!(parse_count("1200").unwrap(), 1200);
        for bad in ["", "0", "-5k", "1.0001k", "abc", "20m", "nan"] {
            assert!(parse_count(bad).is_err(), "{bad}");
        }
    }
}
