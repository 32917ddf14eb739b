//! Per-pass query pools: every logical pass is bracketed by a pipeline-statistics query, a
//! precise occlusion query and two timestamps. Queries live inside the render pass (a query
//! begun in a subpass ends in it), so one render pass can hold many measured passes.

use std::sync::Arc;

use ash::vk;

use super::context::Gpu;
use super::live_objects::ObjectKind;
use crate::error::{Result, VkContext};

/// What one pass's queries returned.
#[derive(Debug, Clone, Copy, Default)]
pub struct RawPassQueries {
    pub vertex_invocations: Option<u64>,
    pub clipping_primitives: Option<u64>,
    pub fragment_invocations: Option<u64>,
    pub samples_passed: u64,
    pub begin_ns: f64,
    pub end_ns: f64,
}

pub struct PassQueryPools {
    gpu: Arc<Gpu>,
    statistics: Option<QueryPool>,
    occlusion: QueryPool,
    timestamps: QueryPool,
    capacity: u32,
    precise: bool,
    /// False when the GPU was opened `without_pass_queries`: nothing is recorded and every
    /// result reads 0 (statistics None).
    recording: bool,
}

// Order of results follows the bit order of the flags: vertex (bit 2), clipping primitives
// (bit 6), fragment (bit 7).
const STATISTICS: vk::QueryPipelineStatisticFlags = vk::QueryPipelineStatisticFlags::from_raw(
    vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS.as_raw()
        | vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES.as_raw()
        | vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS.as_raw(),
);

impl PassQueryPools {
    pub fn new(gpu: &Arc<Gpu>, capacity: u32) -> Result<Self> {
        let device = gpu.raw();
        let features = gpu.device.info.features;
        let make = |ty: vk::QueryType, count: u32, stats: vk::QueryPipelineStatisticFlags| {
            let info = vk::QueryPoolCreateInfo::default().query_type(ty).query_count(count).pipeline_statistics(stats);
            // SAFETY: `device` is alive (`gpu` holds it); statistics are asked for only when the
            // device enabled pipelineStatisticsQuery.
            let raw = unsafe { device.create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
            gpu.created(ObjectKind::QueryPool);
            // Owned at once: a later pool failing drops (destroys) the ones made before it.
            Ok::<_, crate::error::Error>(QueryPool { gpu: gpu.clone(), raw })
        };
        let statistics = if features.pipeline_statistics_query {
            Some(make(vk::QueryType::PIPELINE_STATISTICS, capacity, STATISTICS)?)
        } else {
            None
        };
        let occlusion = make(vk::QueryType::OCCLUSION, capacity, Default::default())?;
        let timestamps = make(vk::QueryType::TIMESTAMP, capacity * 2, Default::default())?;
        Ok(PassQueryPools {
            gpu: gpu.clone(),
            statistics,
            occlusion,
            timestamps,
            capacity,
            precise: features.occlusion_query_precise,
            recording: !gpu.without_pass_queries,
        })
    }

    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    /// Must be recorded outside a render pass, before the frame's first pass.
    pub fn reset(&self, cmd: vk::CommandBuffer) {
        if !self.recording {
            return;
        }
        let device = self.gpu.raw();
        // SAFETY: `cmd` is recording outside a render pass (the caller's contract above); each
        // range is the whole pool.
        unsafe {
            if let Some(pool) = self.statistics.as_ref().map(|p| p.raw) {
                device.cmd_reset_query_pool(cmd, pool, 0, self.capacity);
            }
            device.cmd_reset_query_pool(cmd, self.occlusion.raw, 0, self.capacity);
            device.cmd_reset_query_pool(cmd, self.timestamps.raw, 0, self.capacity * 2);
        }
    }

    /// Opens pass `pass`'s queries; `pass` must be below `capacity` and used once per frame.
    pub fn begin(&self, cmd: vk::CommandBuffer, pass: u32) {
        assert!(pass < self.capacity, "pass {pass} past a query pool of {}", self.capacity);
        if !self.recording {
            return;
        }
        let device = self.gpu.raw();
        let flags = if self.precise { vk::QueryControlFlags::PRECISE } else { vk::QueryControlFlags::empty() };
        // SAFETY: `cmd` is recording; `pass` (and its two timestamps) are inside the pools, which
        // were reset this frame; PRECISE only when the device enabled occlusionQueryPrecise.
        unsafe {
            device.cmd_write_timestamp(cmd, vk::PipelineStageFlags::TOP_OF_PIPE, self.timestamps.raw, pass * 2);
            device.cmd_begin_query(cmd, self.occlusion.raw, pass, flags);
            if let Some(pool) = self.statistics.as_ref().map(|p| p.raw) {
                device.cmd_begin_query(cmd, pool, pass, vk::QueryControlFlags::empty());
            }
        }
    }

    /// Closes the queries `begin` opened for `pass`, in the same subpass.
    pub fn end(&self, cmd: vk::CommandBuffer, pass: u32) {
        assert!(pass < self.capacity, "pass {pass} past a query pool of {}", self.capacity);
        if !self.recording {
            return;
        }
        let device = self.gpu.raw();
        // SAFETY: `cmd` is recording and the queries of `pass` are active (begun by `begin`).
        unsafe {
            if let Some(pool) = self.statistics.as_ref().map(|p| p.raw) {
                device.cmd_end_query(cmd, pool, pass);
            }
            device.cmd_end_query(cmd, self.occlusion.raw, pass);
            device.cmd_write_timestamp(cmd, vk::PipelineStageFlags::BOTTOM_OF_PIPE, self.timestamps.raw, pass * 2 + 1);
        }
    }

    /// Results of the first `count` passes; call after the frame's fence has signalled.
    pub fn results(&self, count: u32) -> Result<Vec<RawPassQueries>> {
        if count == 0 {
            return Ok(Vec::new());
        }
        assert!(count <= self.capacity, "{count} passes past a query pool of {}", self.capacity);
        if !self.recording {
            return Ok(vec![RawPassQueries::default(); count as usize]);
        }
        let device = self.gpu.raw();
        let wait = vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT;
        let mut stats = vec![[0u64; 3]; count as usize];
        if let Some(pool) = self.statistics.as_ref().map(|p| p.raw) {
            // SAFETY: here and in the two reads below, each slice holds exactly the results of
            // the first `count` queries (three statistics, one sample count, two timestamps per
            // pass) as u64 (TYPE_64), inside the pools; all were issued, so WAIT returns.
            unsafe { device.get_query_pool_results(pool, 0, &mut stats, wait) }
                .vk("vkGetQueryPoolResults (statistics)")?;
        }
        let mut samples = vec![0u64; count as usize];
        // SAFETY: as above.
        unsafe { device.get_query_pool_results(self.occlusion.raw, 0, &mut samples, wait) }
            .vk("vkGetQueryPoolResults (occlusion)")?;
        let mut stamps = vec![0u64; count as usize * 2];
        // SAFETY: as above.
        unsafe { device.get_query_pool_results(self.timestamps.raw, 0, &mut stamps, wait) }
            .vk("vkGetQueryPoolResults (timestamps)")?;

        let info = &self.gpu.device.info;
        let period = info.limits.timestamp_period as f64;
        let mask = if info.timestamp_valid_bits >= 64 { u64::MAX } else { (1u64 << info.timestamp_valid_bits) - 1 };
        let has_stats = self.statistics.is_some();
        Ok((0..count as usize)
            .map(|i| {
                let begin = stamps[2 * i] & mask;
                let end = stamps[2 * i + 1] & mask;
                RawPassQueries {
                    vertex_invocations: has_stats.then_some(stats[i][0]),
                    clipping_primitives: has_stats.then_some(stats[i][1]),
                    fragment_invocations: has_stats.then_some(stats[i][2]),
                    samples_passed: samples[i],
                    begin_ns: begin as f64 * period,
                    end_ns: end as f64 * period,
                }
            })
            .collect())
    }
}

/// One query pool, destroyed with its owner.
struct QueryPool {
    gpu: Arc<Gpu>,
    raw: vk::QueryPool,
}

impl Drop for QueryPool {
    fn drop(&mut self) {
        // SAFETY: no pending command uses the pool: every frame is waited for before its
        // results are read, and the renderer owning the pools is dropped after.
        unsafe { self.gpu.raw().destroy_query_pool(self.raw, None) };
        self.gpu.destroyed(ObjectKind::QueryPool);
    }
}
