//! `meadow bench-grass`: GPU time of the grass step alone (timestamp
//! queries around each dispatch) at several blade counts, the figures the
//! paper gives for its grass step (8.5 / 16.9 / 25.8 / 33.5 ms for 50K /
//! 100K / 150K / 200K blades on a GTX 670). The wind is solved for a while
//! first so that the blades move, and then held: only the grass is timed.
//!
//! With `--colliders 0,1,16,128` each count also runs with that many balls
//! rolling round small loops spread over the field (`bench_colliders`), and
//! each row says its cost over the collider-free step of the same count in
//! the same run.

use crate::commands::on_gpu;
use crate::compute::{GrassPass, Simulation};
use crate::error::{Error, Result};
use crate::frame::timing::median_p95;
use crate::frame::BladeBuffer;
use crate::gpu::query::TimestampQueries;
use crate::gpu::{
    Access, BufferUse, CommandPool, DeviceMemory, Gpu, GpuOptions, Recording, ValidationReport,
};
use crate::model::contact::{Collider, ColliderKind, MAX_COLLIDERS};
use crate::model::Blade;
use crate::scene::{field, Scene, MAX_BLADES};
use glam::{Vec2, Vec3};

/// The paper's grass-step times (ms) on a GTX 670, by blade count.
pub const PAPER_GRASS_MS: [(usize, f64); 4] = [
    (50_000, 8.5),
    (100_000, 16.9),
    (150_000, 25.8),
    (200_000, 33.5),
];

/// Wind steps solved before timing by default, so that the grass meets a
/// developed field (`GrassSteps::wind_warmup`).
pub const WIND_WARMUP_STEPS: u32 = 30;

/// The steps of each row: `timed` grass steps after `warmup` untimed
/// ones, all after `wind_warmup` wind steps.
#[derive(Clone, Copy, Debug)]
pub struct GrassSteps {
    pub timed: u32,
    pub warmup: u32,
    /// Wind steps solved first, untimed (`WIND_WARMUP_STEPS` by default;
    /// on lavapipe each of table1's costs a fifth of a second whatever
    /// the blade count, which a check of small counts need not pay).
    pub wind_warmup: u32,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct GrassBenchRow {
    pub blades: usize,
    /// Colliders rolling through the field (beside the scene's own).
    pub colliders: usize,
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
    /// The median step over the same count's without colliders, where
    /// both ran (the goal: at most 2 at 128 colliders).
    pub over_collider_free: Option<f64>,
    /// Blades the last step stepped with the contact (near a collider or
    /// pressed; src/compute/grass_pass.rs).
    pub touching: u64,
}

impl GrassBenchRow {
    /// The memory floor at `copy`'s bandwidth, and the median step over it.
    fn set_floor(&mut self, copy: Option<&CopyBandwidth>) {
        self.floor_ms = copy.map(|c| self.bytes_per_step as f64 / (c.gb_per_s * 1e9) * 1e3);
        self.over_floor = self
            .floor_ms
            .zip(self.step_ms_median)
            .filter(|(f, _)| *f > 0.0)
            .map(|(f, t)| t / f);
    }
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
    /// Wind steps each row solved before its grass steps.
    pub wind_warmup_steps: u32,
    pub device: String,
    pub device_type: String,
    /// The device memory the rows' allocations held at the end and at
    /// most (the largest row's; the bandwidth copy after them is not
    /// counted).
    pub device_memory: DeviceMemory,
    pub rows: Vec<GrassBenchRow>,
    /// None where the device has no timestamps.
    pub copy_bandwidth: Option<CopyBandwidth>,
    pub validation: ValidationReport,
}

/// Where a `bench_grass` run is, told before each row (and before the
/// bandwidth copy that ends it, `row: None`), for a progress display.
#[derive(Clone, Copy, Debug)]
pub struct RowProgress {
    /// Rows done, and the rows and copy in all.
    pub done: usize,
    pub total: usize,
    /// The row about to run: blades and added colliders.
    pub row: Option<(usize, usize)>,
}

/// Times `steps` of `scene` at each count, with each number of
/// `colliders` (`&[0]`: the scene as it is). `on_row` hears of each row
/// before it starts.
pub fn bench_grass(
    scene: &Scene,
    counts: &[usize],
    colliders: &[usize],
    steps: GrassSteps,
    options: &GpuOptions,
    on_row: &mut dyn FnMut(RowProgress),
) -> Result<GrassBench> {
    let GrassSteps {
        timed,
        warmup,
        wind_warmup,
    } = steps;
    if counts.is_empty() || counts.iter().any(|&n| n == 0 || n > MAX_BLADES) {
        return Err(Error::InvalidInput(format!(
            "blade counts {counts:?} are not allowed, use 1..={MAX_BLADES} each"
        )));
    }
    if !(1..=10_000).contains(&timed) || warmup > 10_000 || wind_warmup > 10_000 {
        return Err(Error::InvalidInput(format!(
            "--steps {timed} / --warmup {warmup} / --wind-warmup {wind_warmup} are not allowed, use 1..=10000, 0..=10000 and 0..=10000"
        )));
    }
    if colliders.is_empty()
        || colliders
            .iter()
            .any(|&n| n + scene.colliders.len() > MAX_COLLIDERS)
    {
        return Err(Error::InvalidInput(format!(
            "--colliders {colliders:?} is not allowed: a step simulates at most {MAX_COLLIDERS} colliders and the scene has {} of its own; use 0..={} each",
            scene.colliders.len(),
            MAX_COLLIDERS - scene.colliders.len()
        )));
    }
    scene.wind_grid()?;
    scene.grass.dynamics.validate()?;
    let ((rows, copy_bandwidth, info, device_memory), validation) = on_gpu(options, |gpu| {
        // Refused before the work; measured after it, so a run that fails
        // on the way (out of memory, a lost device) has not waited for it.
        gpu.check_fits("the bandwidth copy", 2 * COPY_BYTES)?;
        let mut rows = Vec::new();
        let total = counts.len() * colliders.len() + 1;
        for &n in counts {
            for &c in colliders {
                on_row(RowProgress {
                    done: rows.len(),
                    total,
                    row: Some((n, c)),
                });
                rows.push(bench_count(gpu, scene, n, c, steps)?);
            }
        }
        on_row(RowProgress {
            done: rows.len(),
            total,
            row: None,
        });
        let device_memory = gpu.device_memory();
        let copy = copy_bandwidth(gpu)?;
        for row in &mut rows {
            row.set_floor(copy.as_ref());
        }
        compare_with_collider_free(&mut rows);
        Ok((rows, copy, gpu.info().clone(), device_memory))
    })?;
    let bench = GrassBench {
        scene: scene.name.clone(),
        wind_warmup_steps: wind_warmup,
        device: info.name,
        device_type: info.device_type,
        device_memory,
        rows,
        copy_bandwidth,
        validation,
    };
    bench.validation.check()?;
    Ok(bench)
}

/// Each row's median over the collider-free row of its blade count.
fn compare_with_collider_free(rows: &mut [GrassBenchRow]) {
    let free: Vec<(usize, Option<f64>)> = rows
        .iter()
        .filter(|r| r.colliders == 0)
        .map(|r| (r.blades, r.step_ms_median))
        .collect();
    for row in rows.iter_mut() {
        row.over_collider_free = free
            .iter()
            .find(|(blades, _)| *blades == row.blades)
            .and_then(|(_, ms)| *ms)
            .zip(row.step_ms_median)
            .filter(|(free, _)| *free > 0.0)
            .map(|(free, ms)| ms / free);
    }
}

/// `n` balls 0.3 m in radius, each rolling at 1.5 m/s round its own 2 m
/// square loop, their loops spread over the field from `lo` to `hi`
/// (x, z) on a lattice as square as `n` allows: the load of many walkers
/// and balls in one meadow.
pub fn bench_colliders(n: usize, lo: Vec2, hi: Vec2) -> Vec<Collider> {
    let across = (n as f32).sqrt().ceil().max(1.0) as usize;
    let rows = n.div_ceil(across).max(1);
    let cell = (hi - lo) / Vec2::new(across as f32, rows as f32);
    (0..n)
        .map(|i| {
            let centre =
                lo + cell * Vec2::new((i % across) as f32 + 0.5, (i / across) as f32 + 0.5);
            let corner = |dx: f32, dz: f32| Vec3::new(centre.x + dx, 0.3, centre.y + dz);
            Collider {
                kind: ColliderKind::Sphere,
                radius: 0.3,
                height: 0.0,
                position: Vec3::ZERO,
                path: vec![
                    corner(-1.0, -1.0),
                    corner(1.0, -1.0),
                    corner(1.0, 1.0),
                    corner(-1.0, 1.0),
                ],
                path_speed: 1.5,
                closed: true,
                roll: true,
                ..Default::default()
            }
        })
        .collect()
}

/// `scene` with `count` blades and, with `colliders`, that many balls
/// rolling laps over them (`bench_colliders`), and its blades.
fn bench_scene(scene: &Scene, count: usize, colliders: usize) -> Result<(Scene, Vec<Blade>)> {
    let mut scene = scene.clone();
    scene.set_blade_count(count)?;
    let blades = scene.field()?;
    if colliders > 0 {
        let (lo, hi) = blades.iter().fold(
            (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY)),
            |(lo, hi), b| {
                let root = Vec2::new(b.rest[0].x, b.rest[0].z);
                (lo.min(root), hi.max(root))
            },
        );
        scene.colliders.extend(bench_colliders(colliders, lo, hi));
    }
    Ok((scene, blades))
}

/// `warmup` grass steps, then `steps` timed each between two timestamps
/// where the device has them.
fn record_timed_steps(
    rec: &Recording,
    grass: &GrassPass,
    timestamps: Option<&TimestampQueries>,
    (warmup, steps): (u32, u32),
    dt: f32,
) {
    let end_time = |step: u32| crate::model::contact::step_end_time(step as u64, dt);
    for n in 0..warmup {
        grass.record_step(rec, 0, end_time(n));
    }
    if let Some(t) = timestamps {
        t.reset(rec);
    }
    for n in 0..steps {
        if let Some(t) = timestamps {
            t.stamp(rec, n, false);
        }
        grass.record_step(rec, 0, end_time(warmup + n));
        if let Some(t) = timestamps {
            t.stamp(rec, n, true);
        }
    }
}

fn bench_count(
    gpu: &Gpu,
    scene: &Scene,
    count: usize,
    colliders: usize,
    GrassSteps {
        timed: steps,
        warmup,
        wind_warmup,
    }: GrassSteps,
) -> Result<GrassBenchRow> {
    let (scene, blades) = bench_scene(scene, count, colliders)?;
    let dynamic = field::dynamic_blades(&blades, &scene.grass.dynamics, scene.seed)?;
    gpu.check_fits(
        &format!("{count} blades"),
        crate::compute::grass_pass::device_bytes(count, !scene.colliders.is_empty()),
    )?;

    // Everything made first, through the simulation every command uses,
    // then the work: a run that cannot have its memory fails before any.
    let dt = scene.wind.dt;
    let commands = CommandPool::new(gpu, "grass bench commands")?;
    let vertices = BladeBuffer::uninitialised(gpu, "grass bench vertices", count)?;
    let mut simulation = Simulation::new(gpu, &commands, &scene, &dynamic, vertices.buffer())?;
    let timestamps = TimestampQueries::new(gpu, steps, "grass step timestamps")?;
    let rec = commands.begin()?;
    for i in 0..wind_warmup {
        simulation.wind_mut().record_step(&rec, i as f32 * dt, dt);
    }
    rec.submit_and_wait("wind warm-up")?;
    let grass = simulation.grass().ok_or_else(|| {
        Error::InvalidInput(
            "bench-grass steps the patches' blades and this scene's only grass is a [grass.cover]; add a [[grass.meadow]] or pick another scene".into(),
        )
    })?;

    let rec = commands.begin()?;
    record_timed_steps(&rec, grass, timestamps.as_ref(), (warmup, steps), dt);
    rec.submit_and_wait("grass steps")?;
    let times = match &timestamps {
        Some(t) => t.read_ms(steps)?,
        None => Vec::new(),
    };
    let timing = median_p95(&times);
    let touching = grass.read_touching(gpu, &commands)?;
    Ok(GrassBenchRow {
        bytes_per_step: crate::compute::grass_pass::bytes_per_step(count),
        floor_ms: None,
        over_floor: None,
        over_collider_free: None,
        touching,
        blades: count,
        colliders,
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
    let commands = CommandPool::new(gpu, "bandwidth copy commands")?;
    let rec = commands.begin()?;
    // Written once first, so no page is touched for the first time while
    // timed.
    rec.fill_buffer(&src, 0);
    rec.fill_buffer(&dst, 0);
    timestamps.reset(&rec);
    for n in 0..COPIES {
        rec.uses(&[
            BufferUse::new(&src, Access::COPY_READ),
            BufferUse::new(&dst, Access::COPY_WRITE),
        ]);
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
