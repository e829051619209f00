//! GPU queries: pipeline statistics around the grass draw, which prove the
//! level of detail (segments per blade) and count the work each stage did.

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
    period_ns: f64,
    valid_mask: u64,
}

impl TimestampQueries {
    /// Room for `pairs` begin/end pairs; `None` where the queue has no timestamps.
    pub fn new(gpu: &Gpu, pairs: u32, name: &str) -> Result<Option<Self>> {
        if !gpu.info().timestamps {
            return Ok(None);
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(2 * pairs);
        // SAFETY: valid create info on a live device.
        let pool = unsafe { gpu.device.raw.create_query_pool(&info, None) }
            .vk_context("vkCreateQueryPool", name)?;
        gpu.device.name(pool, name);
        let bits = gpu.device.timestamp_valid_bits;
        Ok(Some(Self {
            pool,
            capacity: pairs,
            period_ns: gpu.device.limits().timestamp_period as f64,
            valid_mask: if bits >= 64 {
                u64::MAX
            } else {
                (1u64 << bits) - 1
            },
        }))
    }

    pub fn reset(&self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        // SAFETY: recording, outside any render pass instance.
        unsafe {
            gpu.device
                .raw
                .cmd_reset_query_pool(cmd, self.pool, 0, 2 * self.capacity)
        };
    }

    /// Writes the begin (`end == false`) or end stamp of pair `pair`.
    pub fn stamp(&self, gpu: &Gpu, cmd: vk::CommandBuffer, pair: u32, end: bool) {
        let stage = if end {
            vk::PipelineStageFlags2::ALL_COMMANDS
        } else {
            vk::PipelineStageFlags2::TOP_OF_PIPE
        };
        // SAFETY: the query index is within the pool; recording.
        unsafe {
            gpu.device
                .raw
                .cmd_write_timestamp2(cmd, stage, self.pool, 2 * pair + end as u32)
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
        .vk_context("vkGetQueryPoolResults", "timestamps")?;
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
