//! GPU queries: pipeline statistics around the grass draw, which prove the
//! level of detail (segments per blade) and count the work each stage did;
//! timestamps around each phase of a frame.

use ash::vk;

use crate::error::{Result, VkResultExt};
use crate::gpu::Gpu;

/// Counters read back for one draw. Their order is the order of the bits in
/// `STATISTICS` (Vulkan returns them sorted by bit).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct PipelineStatistics {
    pub vertex_shader_invocations: u64,
    pub geometry_shader_invocations: u64,
    pub geometry_shader_primitives: u64,
    pub clipping_primitives: u64,
    pub fragment_shader_invocations: u64,
    pub tessellation_control_patches: u64,
    pub tessellation_evaluation_invocations: u64,
}

const STATISTICS: vk::QueryPipelineStatisticFlags = vk::QueryPipelineStatisticFlags::from_raw(
    vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS.as_raw()
        | vk::QueryPipelineStatisticFlags::GEOMETRY_SHADER_INVOCATIONS.as_raw()
        | vk::QueryPipelineStatisticFlags::GEOMETRY_SHADER_PRIMITIVES.as_raw()
        | vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES.as_raw()
        | vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS.as_raw()
        | vk::QueryPipelineStatisticFlags::TESSELLATION_CONTROL_SHADER_PATCHES.as_raw()
        | vk::QueryPipelineStatisticFlags::TESSELLATION_EVALUATION_SHADER_INVOCATIONS.as_raw(),
);
const COUNTERS: usize = 7;

/// One pipeline-statistics query, or nothing where the device lacks them.
pub struct StatisticsQuery {
    pool: Option<vk::QueryPool>,
}

impl StatisticsQuery {
    pub fn new(gpu: &Gpu) -> Result<Self> {
        if !gpu.device.pipeline_statistics {
            return Ok(Self { pool: None });
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .query_count(1)
            .pipeline_statistics(STATISTICS);
        // SAFETY: the feature was enabled at device creation.
        let pool = unsafe { gpu.device.raw.create_query_pool(&info, None) }
            .vk_context("vkCreateQueryPool", "pipeline statistics")?;
        gpu.device.name(pool, "grass pipeline statistics");
        Ok(Self { pool: Some(pool) })
    }

    /// Records the reset; must be outside a render pass instance.
    pub fn reset(&self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        if let Some(pool) = self.pool {
            // SAFETY: recording, outside rendering.
            unsafe { gpu.device.raw.cmd_reset_query_pool(cmd, pool, 0, 1) };
        }
    }

    pub fn begin(&self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        if let Some(pool) = self.pool {
            unsafe {
                gpu.device
                    .raw
                    .cmd_begin_query(cmd, pool, 0, vk::QueryControlFlags::empty())
            };
        }
    }

    pub fn end(&self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        if let Some(pool) = self.pool {
            unsafe { gpu.device.raw.cmd_end_query(cmd, pool, 0) };
        }
    }

    /// Reads the counters after the submission finished; `None` without support.
    pub fn read(&self, gpu: &Gpu) -> Result<Option<PipelineStatistics>> {
        let Some(pool) = self.pool else {
            return Ok(None);
        };
        // One query whose result is COUNTERS 64-bit values.
        let mut data = [[0u64; COUNTERS]; 1];
        // SAFETY: the query was begun and ended in a submission already waited for.
        unsafe {
            gpu.device.raw.get_query_pool_results(
                pool,
                0,
                &mut data,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk_context("vkGetQueryPoolResults", "pipeline statistics")?;
        let data = data[0];
        Ok(Some(PipelineStatistics {
            vertex_shader_invocations: data[0],
            geometry_shader_invocations: data[1],
            geometry_shader_primitives: data[2],
            clipping_primitives: data[3],
            fragment_shader_invocations: data[4],
            tessellation_control_patches: data[5],
            tessellation_evaluation_invocations: data[6],
        }))
    }

    pub fn destroy(self, gpu: &Gpu) {
        if let Some(pool) = self.pool {
            unsafe { gpu.device.raw.destroy_query_pool(pool, None) };
        }
    }
}

/// Timestamp pairs around repeated GPU work (one pair per repetition),
/// converted with the device's `timestampPeriod` and masked to its valid bits.
pub struct TimestampQueries {
    pool: vk::QueryPool,
    capacity: u32,
    name: &'static str,
    period_ns: f64,
    valid_mask: u64,
}

impl TimestampQueries {
    /// Room for `pairs` begin/end pairs; `None` where the queue has no timestamps.
    pub fn new(gpu: &Gpu, pairs: u32, name: &'static str) -> Result<Option<Self>> {
        if !gpu.info().timestamps {
            return Ok(None);
        }
        let pool = create_timestamp_pool(gpu, pairs, name)?;
        let bits = gpu.device.timestamp_valid_bits;
        Ok(Some(Self {
            pool,
            capacity: pairs,
            name,
            period_ns: gpu.device.limits().timestamp_period as f64,
            valid_mask: if bits >= 64 {
                u64::MAX
            } else {
                (1u64 << bits) - 1
            },
        }))
    }

    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    /// Makes room for `pairs` pairs (at least doubling). Only between
    /// submissions: the caller has waited for the last one that used the pool.
    pub fn reserve(&mut self, gpu: &Gpu, pairs: u32) -> Result<()> {
        if pairs <= self.capacity {
            return Ok(());
        }
        let capacity = pairs.max(self.capacity.saturating_mul(2));
        let pool = create_timestamp_pool(gpu, capacity, self.name)?;
        // SAFETY: no submission using the old pool is in flight (above).
        unsafe { gpu.device.raw.destroy_query_pool(self.pool, None) };
        self.pool = pool;
        self.capacity = capacity;
        Ok(())
    }

    pub fn reset(&self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        // SAFETY: recording, outside any render pass instance.
        unsafe {
            gpu.device
                .raw
                .cmd_reset_query_pool(cmd, self.pool, 0, 2 * self.capacity)
        };
    }

    /// Writes the begin (`end == false`) or end stamp of pair `pair`. Both
    /// at ALL_COMMANDS, as `PhaseTimer` does: a pair measures from the end
    /// of the work before it to the end of its own.
    pub fn stamp(&self, gpu: &Gpu, cmd: vk::CommandBuffer, pair: u32, end: bool) {
        // SAFETY: the query index is within the pool; recording.
        unsafe {
            gpu.device.raw.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                2 * pair + end as u32,
            )
        };
    }

    /// Milliseconds of the first `pairs` pairs, after the submission finished.
    pub fn read_ms(&self, gpu: &Gpu, pairs: u32) -> Result<Vec<f64>> {
        let mut data = vec![0u64; 2 * pairs as usize];
        // SAFETY: every query in range was written by a finished submission.
        unsafe {
            gpu.device.raw.get_query_pool_results(
                self.pool,
                0,
                &mut data,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk_context("vkGetQueryPoolResults", self.name)?;
        Ok(data
            .chunks_exact(2)
            .map(|p| {
                let ticks =
                    (p[1] & self.valid_mask).wrapping_sub(p[0] & self.valid_mask) & self.valid_mask;
                ticks as f64 * self.period_ns / 1e6
            })
            .collect())
    }

    pub fn destroy(self, gpu: &Gpu) {
        // SAFETY: no submission using the pool is in flight.
        unsafe { gpu.device.raw.destroy_query_pool(self.pool, None) };
    }
}

/// The phases of a frame that are timed apart. `GrassDraw` lies inside
/// `Colour` (the blade draw alone, without sky and ground, for the floor
/// comparison); `Frame` spans everything.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// Wind solver steps (forces, advection, divergence, Jacobi, projection).
    Wind,
    /// Grass dynamics steps (swing, bend, twist).
    Grass,
    /// The depth-only pass from the sun into the shadow map.
    Shadow,
    /// Sky, ground and grass into the multisampled image, resolved at the
    /// end of the pass.
    Colour,
    /// The blade draw alone (vert/tesc/tese/geom/frag), inside `Colour`.
    GrassDraw,
    /// The copy of the resolved image into the host-visible buffer.
    Readback,
    /// From the first command of the frame to the last.
    Frame,
}

impl Phase {
    pub const ALL: [Phase; 7] = [
        Phase::Wind,
        Phase::Grass,
        Phase::Shadow,
        Phase::Colour,
        Phase::GrassDraw,
        Phase::Readback,
        Phase::Frame,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Phase::Wind => "wind",
            Phase::Grass => "grass",
            Phase::Shadow => "shadow",
            Phase::Colour => "colour",
            Phase::GrassDraw => "grass_draw",
            Phase::Readback => "readback",
            Phase::Frame => "frame",
        }
    }
}

/// One value per phase of a frame, named as the phases are in reports.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct PerPhase<T> {
    pub wind: T,
    pub grass: T,
    pub shadow: T,
    pub colour: T,
    pub grass_draw: T,
    pub readback: T,
    pub frame: T,
}

impl<T> PerPhase<T> {
    /// Each phase's value from `f`.
    pub fn from_fn(mut f: impl FnMut(Phase) -> T) -> Self {
        Self {
            wind: f(Phase::Wind),
            grass: f(Phase::Grass),
            shadow: f(Phase::Shadow),
            colour: f(Phase::Colour),
            grass_draw: f(Phase::GrassDraw),
            readback: f(Phase::Readback),
            frame: f(Phase::Frame),
        }
    }

    pub fn get_mut(&mut self, phase: Phase) -> &mut T {
        match phase {
            Phase::Wind => &mut self.wind,
            Phase::Grass => &mut self.grass,
            Phase::Shadow => &mut self.shadow,
            Phase::Colour => &mut self.colour,
            Phase::GrassDraw => &mut self.grass_draw,
            Phase::Readback => &mut self.readback,
            Phase::Frame => &mut self.frame,
        }
    }
}

impl<T: Copy> PerPhase<T> {
    pub fn get(&self, phase: Phase) -> T {
        match phase {
            Phase::Wind => self.wind,
            Phase::Grass => self.grass,
            Phase::Shadow => self.shadow,
            Phase::Colour => self.colour,
            Phase::GrassDraw => self.grass_draw,
            Phase::Readback => self.readback,
            Phase::Frame => self.frame,
        }
    }
}

/// GPU milliseconds of one frame per phase (a phase recorded several times,
/// such as one wind step per simulation step, is summed; one not recorded
/// is 0: a frame with no simulation step has no wind work).
pub type FrameTimings = PerPhase<f64>;

/// A begin/end pair handed out by `PhaseTimer::begin`.
#[derive(Clone, Copy, Debug)]
pub struct Span(Option<u32>);

/// Timestamps around the phases of one frame: one query pool, reset at the
/// start of each frame's command buffer, read after the frame's fence (the
/// frame loop waits for each frame anyway, for its read-back, so reading
/// the results never stalls the next frame). Both stamps of a pair are
/// written at ALL_COMMANDS: a pair measures from the end of the work before
/// it to the end of its own.
pub struct PhaseTimer {
    queries: TimestampQueries,
    /// The phase of each pair written this frame, in order.
    pairs: Vec<Phase>,
}

impl PhaseTimer {
    /// Room for `pairs` pairs; `None` where the device has no timestamps.
    pub fn new(gpu: &Gpu, pairs: u32) -> Result<Option<Self>> {
        Ok(
            TimestampQueries::new(gpu, pairs, "frame phase timestamps")?.map(|queries| Self {
                queries,
                pairs: Vec::new(),
            }),
        )
    }

    /// Makes room for `pairs` pairs. Only between frames: the caller has
    /// waited for the last submission that used the pool.
    pub fn reserve(&mut self, gpu: &Gpu, pairs: u32) -> Result<()> {
        self.queries.reserve(gpu, pairs)
    }

    /// Starts a frame: resets every query (outside any render pass).
    pub fn reset(&mut self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        self.pairs.clear();
        self.queries.reset(gpu, cmd);
    }

    /// Writes the begin stamp of a `phase` pair (not timed when the pool
    /// is full: `reserve` sizes it for the frame).
    pub fn begin(&mut self, gpu: &Gpu, cmd: vk::CommandBuffer, phase: Phase) -> Span {
        let index = self.pairs.len() as u32;
        if index >= self.queries.capacity() {
            return Span(None);
        }
        self.pairs.push(phase);
        self.queries.stamp(gpu, cmd, index, false);
        Span(Some(index))
    }

    pub fn end(&self, gpu: &Gpu, cmd: vk::CommandBuffer, span: Span) {
        if let Some(index) = span.0 {
            self.queries.stamp(gpu, cmd, index, true);
        }
    }

    /// The frame's phases in ms, after its submission finished.
    pub fn read(&self, gpu: &Gpu) -> Result<FrameTimings> {
        let mut times = FrameTimings::default();
        if self.pairs.is_empty() {
            return Ok(times);
        }
        let ms = self.queries.read_ms(gpu, self.pairs.len() as u32)?;
        for (phase, ms) in self.pairs.iter().zip(ms) {
            *times.get_mut(*phase) += ms;
        }
        Ok(times)
    }

    pub fn destroy(self, gpu: &Gpu) {
        self.queries.destroy(gpu);
    }
}

fn create_timestamp_pool(gpu: &Gpu, pairs: u32, name: &str) -> Result<vk::QueryPool> {
    let queries = pairs.checked_mul(2).ok_or_else(|| {
        crate::error::Error::InvalidInput(format!("{name}: {pairs} timestamp pairs are too many"))
    })?;
    let info = vk::QueryPoolCreateInfo::default()
        .query_type(vk::QueryType::TIMESTAMP)
        .query_count(queries);
    // SAFETY: valid create info on a live device.
    let pool = unsafe { gpu.device.raw.create_query_pool(&info, None) }
        .vk_context("vkCreateQueryPool", name)?;
    gpu.device.name(pool, name);
    Ok(pool)
}

/// Median and 95th percentile of one quantity over many frames.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Spread {
    pub median: f64,
    pub p95: f64,
}

impl Spread {
    pub fn of(values: &[f64]) -> Option<Self> {
        median_p95(values).map(|(median, p95)| Self { median, p95 })
    }
}

/// Median and 95th percentile of a set of timings.
pub fn median_p95(values: &[f64]) -> Option<(f64, f64)> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    Some((at(0.5), at(0.95)))
}

/// Median and p95 GPU ms of each phase over a run of frames.
pub type PhaseSpreads = PerPhase<Spread>;

/// Timings of a run of frames, as `report.json` and `bench.json` hold them.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TimingSummary {
    /// Frames the figures cover.
    pub frames: usize,
    /// GPU ms per phase (timestamp queries); None when unavailable, with
    /// the reason in `gpu_unavailable` (never reported as zero).
    pub gpu_ms: Option<PhaseSpreads>,
    pub gpu_unavailable: Option<String>,
    /// Wall-clock ms per frame on the host: recording, submission, the GPU
    /// work and the wait for the read-back (not PNG encoding).
    pub wall_frame_ms: Option<Spread>,
    /// 1000 / the median wall-clock frame.
    pub fps: Option<f64>,
}

impl TimingSummary {
    /// From each frame's GPU timings (None: no timestamps on this device)
    /// and wall-clock ms.
    pub fn of(gpu: &[Option<FrameTimings>], wall_ms: &[f64]) -> Self {
        let all: Option<Vec<FrameTimings>> = gpu.iter().copied().collect();
        let gpu_ms = all.filter(|v| !v.is_empty()).map(|v| {
            PhaseSpreads::from_fn(|p| {
                Spread::of(&v.iter().map(|t| t.get(p)).collect::<Vec<_>>()).expect("not empty")
            })
        });
        let gpu_unavailable = match (&gpu_ms, gpu.is_empty()) {
            (Some(_), _) => None,
            (None, true) => Some("no frames were timed".to_string()),
            (None, false) => Some(
                "the device has no timestamp queries on its graphics+compute queue".to_string(),
            ),
        };
        let wall = Spread::of(wall_ms);
        Self {
            frames: wall_ms.len(),
            gpu_ms,
            gpu_unavailable,
            wall_frame_ms: wall,
            fps: wall.filter(|w| w.median > 0.0).map(|w| 1000.0 / w.median),
        }
    }

    /// A short table for the terminal.
    pub fn table(&self) -> String {
        let mut out = String::new();
        match &self.gpu_ms {
            Some(g) => {
                out += &format!(
                    "GPU ms per frame over {} frames (timestamps): phase, median, p95\n",
                    self.frames
                );
                for p in Phase::ALL {
                    let s = g.get(p);
                    out += &format!("  {:<11} {:>9.3} {:>9.3}\n", p.name(), s.median, s.p95);
                }
            }
            None => {
                out += &format!(
                    "GPU time per phase: unavailable ({})\n",
                    self.gpu_unavailable.as_deref().unwrap_or("unknown")
                );
            }
        }
        if let (Some(w), Some(fps)) = (self.wall_frame_ms, self.fps) {
            out += &format!(
                "wall clock per frame: median {:.3} ms, p95 {:.3} ms ({fps:.2} FPS)\n",
                w.median, w.p95
            );
        }
        out
    }
}
