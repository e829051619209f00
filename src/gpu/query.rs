//! GPU queries: pipeline statistics around one draw, and timestamp pairs
//! around recorded work, converted with the device's `timestampPeriod` and
//! masked to its valid bits. What the spans mean is the caller's: a
//! `SpanTimer` labels each pair with a value of the caller's type.

use ash::vk;

use crate::error::{Error, Result, VkResultExt};
use crate::gpu::owned::Owned;
use crate::gpu::recording::Recording;
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
    pool: Option<Owned<vk::QueryPool>>,
}

impl StatisticsQuery {
    pub fn new(gpu: &Gpu, name: &str) -> Result<Self> {
        let device = gpu.device();
        if !device.pipeline_statistics {
            return Ok(Self { pool: None });
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .query_count(1)
            .pipeline_statistics(STATISTICS);
        // SAFETY: the feature was enabled at device creation.
        let pool = unsafe { device.raw.create_query_pool(&info, None) }
            .vk_context("vkCreateQueryPool", name)?;
        Ok(Self {
            pool: Some(Owned::new(device, pool, name)),
        })
    }

    /// Records the reset; must be outside a render pass instance.
    pub fn reset(&self, rec: &Recording) {
        if let Some(pool) = &self.pool {
            // SAFETY: recording, outside rendering; query 0 exists.
            unsafe {
                rec.device
                    .raw
                    .cmd_reset_query_pool(rec.cmd, pool.raw(), 0, 1)
            };
        }
    }

    pub fn begin(&self, rec: &Recording) {
        if let Some(pool) = &self.pool {
            // SAFETY: recording; the query was reset earlier in this buffer.
            unsafe {
                rec.device.raw.cmd_begin_query(
                    rec.cmd,
                    pool.raw(),
                    0,
                    vk::QueryControlFlags::empty(),
                )
            };
        }
    }

    pub fn end(&self, rec: &Recording) {
        if let Some(pool) = &self.pool {
            // SAFETY: recording, after `begin` in the same render pass.
            unsafe { rec.device.raw.cmd_end_query(rec.cmd, pool.raw(), 0) };
        }
    }

    /// Reads the counters after the submission finished; `None` without support.
    pub fn read(&self) -> Result<Option<PipelineStatistics>> {
        let Some(pool) = &self.pool else {
            return Ok(None);
        };
        // One query whose result is COUNTERS 64-bit values.
        let mut data = [[0u64; COUNTERS]; 1];
        // SAFETY: the query was begun and ended in a submission already waited for.
        unsafe {
            pool.device().raw.get_query_pool_results(
                pool.raw(),
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
}

/// Timestamp pairs around repeated GPU work (one pair per repetition).
pub struct TimestampQueries {
    pool: Owned<vk::QueryPool>,
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
        let pool = timestamp_pool(gpu, pairs, name)?;
        let bits = gpu.device().timestamp_valid_bits;
        Ok(Some(Self {
            pool,
            capacity: pairs,
            name,
            period_ns: gpu.limits().timestamp_period as f64,
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
        self.pool = timestamp_pool(gpu, capacity, self.name)?;
        self.capacity = capacity;
        Ok(())
    }

    pub fn reset(&self, rec: &Recording) {
        // SAFETY: recording, outside any render pass instance; the range
        // lies within the pool.
        unsafe {
            rec.device
                .raw
                .cmd_reset_query_pool(rec.cmd, self.pool.raw(), 0, 2 * self.capacity)
        };
    }

    /// Writes the begin (`end == false`) or end stamp of pair `pair`. Both
    /// at ALL_COMMANDS: a pair measures from the end of the work before it
    /// to the end of its own.
    pub fn stamp(&self, rec: &Recording, pair: u32, end: bool) {
        debug_assert!(pair < self.capacity);
        // SAFETY: recording; the query index is within the pool.
        unsafe {
            rec.device.raw.cmd_write_timestamp2(
                rec.cmd,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool.raw(),
                2 * pair + end as u32,
            )
        };
    }

    /// Milliseconds of the first `pairs` pairs, after the submission finished.
    pub fn read_ms(&self, pairs: u32) -> Result<Vec<f64>> {
        let mut data = vec![0u64; 2 * pairs as usize];
        // SAFETY: every query in range was written by a finished submission.
        unsafe {
            self.pool.device().raw.get_query_pool_results(
                self.pool.raw(),
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
}

fn timestamp_pool(gpu: &Gpu, pairs: u32, name: &str) -> Result<Owned<vk::QueryPool>> {
    let queries = pairs.checked_mul(2).ok_or_else(|| {
        Error::InvalidInput(format!("{name}: {pairs} timestamp pairs are too many"))
    })?;
    let info = vk::QueryPoolCreateInfo::default()
        .query_type(vk::QueryType::TIMESTAMP)
        .query_count(queries);
    let device = gpu.device();
    // SAFETY: a valid create info on a live device.
    let pool = unsafe { device.raw.create_query_pool(&info, None) }
        .vk_context("vkCreateQueryPool", name)?;
    Ok(Owned::new(device, pool, name))
}

/// A begin/end pair handed out by `SpanTimer::begin`.
#[derive(Clone, Copy, Debug)]
pub struct Span(Option<u32>);

/// Timestamps around labelled spans of one submission: one query pool,
/// reset at the start of each recording, read after its fence.
pub struct SpanTimer<L> {
    queries: TimestampQueries,
    /// The label of each pair written this submission, in order.
    labels: Vec<L>,
}

impl<L: Copy> SpanTimer<L> {
    /// Room for `pairs` spans; `None` where the device has no timestamps.
    pub fn new(gpu: &Gpu, pairs: u32, name: &'static str) -> Result<Option<Self>> {
        Ok(
            TimestampQueries::new(gpu, pairs, name)?.map(|queries| Self {
                queries,
                labels: Vec::new(),
            }),
        )
    }

    /// Makes room for `pairs` spans. Only between submissions.
    pub fn reserve(&mut self, gpu: &Gpu, pairs: u32) -> Result<()> {
        self.queries.reserve(gpu, pairs)
    }

    /// Starts a submission: resets every query (outside any render pass).
    pub fn reset(&mut self, rec: &Recording) {
        self.labels.clear();
        self.queries.reset(rec);
    }

    /// Writes the begin stamp of a `label` span (not timed when the pool
    /// is full: `reserve` sizes it).
    pub fn begin(&mut self, rec: &Recording, label: L) -> Span {
        let index = self.labels.len() as u32;
        if index >= self.queries.capacity() {
            return Span(None);
        }
        self.labels.push(label);
        self.queries.stamp(rec, index, false);
        Span(Some(index))
    }

    pub fn end(&self, rec: &Recording, span: Span) {
        if let Span(Some(index)) = span {
            self.queries.stamp(rec, index, true);
        }
    }

    /// Each span's label and milliseconds, after the submission finished.
    pub fn read(&self) -> Result<Vec<(L, f64)>> {
        if self.labels.is_empty() {
            return Ok(Vec::new());
        }
        let ms = self.queries.read_ms(self.labels.len() as u32)?;
        Ok(self.labels.iter().copied().zip(ms).collect())
    }
}
