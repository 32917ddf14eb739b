//! Per-pass fill-rate counters, as the frame's queries returned them.
//!
//! Two different figures are kept apart on purpose:
//! - `fragment_invocations` (pipeline statistics) counts fragment shader invocations. On
//!   lavapipe this is not a pixel count: it is 16 x the 4x4 pixel blocks each triangle touches,
//!   depth-rejected blocks included (docs/design/lavapipe.md). Hardware differs again (2x2 quads).
//! - `samples_passed` (precise occlusion query) counts samples that passed the depth and stencil
//!   tests: exact, the same on every conformant device.

use serde::Serialize;

use super::instances::{
    group_bandwidth, group_bytes_per_sample, group_fixed_bandwidth, RenderPassInstance, RenderPassSums,
};
use super::plan::DrawKind;
use crate::frame::bandwidth::Bandwidth;
use crate::frame::render_pass::RenderPassTraffic;
use crate::gpu::frame_submission::CpuPhases;
use crate::gpu::queries::RawPassQueries;

#[derive(Debug, Clone, Serialize)]
pub struct PassCounters {
    pub name: String,
    /// What the technique drew in the pass itself, as its draw kind describes it (`None` for
    /// the passes the recorder draws: objects, full screen). Found by [`FrameCounters::drawing`].
    #[serde(skip)]
    pub own_draw: Option<&'static str>,
    /// The light (index into the scene's lights) the pass was planned for, in a per-light loop
    /// (`PlannedPass::light`): with `own_draw`, how a technique finds its passes for one light.
    #[serde(skip)]
    pub light: Option<u8>,
    pub draws: u32,
    /// State and draw commands the pass recorded: binds, pushes, scissors and viewports, draws
    /// and clears (`Activity::commands`). Exact, and on lavapipe most of the CPU a pass costs
    /// the render thread.
    pub commands: u32,
    /// Vertex shader invocations (pipeline statistics; None where the device lacks them).
    pub vertex_invocations: Option<u64>,
    /// Primitives that left the clipper (pipeline statistics).
    pub clipping_primitives: Option<u64>,
    /// Fragment shader invocations (pipeline statistics; see the module docs for lavapipe's rule).
    pub fragment_invocations: Option<u64>,
    /// Samples that passed depth/stencil tests (precise occlusion query): exact.
    pub samples_passed: u64,
    /// GPU time between the pass's two timestamps, in milliseconds.
    pub gpu_ms: f64,
    /// Start of the pass relative to the frame's first timestamp, in milliseconds.
    pub start_ms: f64,
    /// Indices of the render pass instances its draws went into (`FrameCounters::
    /// render_pass_instances`): the frame's, or the ones a prepass began; none for a pass that
    /// only copies.
    pub render_pass_instances: Vec<u32>,
}

impl PassCounters {
    pub(crate) fn from_queries(
        name: String,
        (own_draw, light): (Option<&'static str>, Option<u8>),
        (draws, commands): (u32, u32),
        render_pass_instances: Vec<u32>,
        raw: &RawPassQueries,
        frame_start_ns: f64,
    ) -> Self {
        PassCounters {
            name,
            own_draw,
            light,
            draws,
            commands,
            vertex_invocations: raw.vertex_invocations,
            clipping_primitives: raw.clipping_primitives,
            fragment_invocations: raw.fragment_invocations,
            samples_passed: raw.samples_passed,
            gpu_ms: (raw.end_ns - raw.begin_ns).max(0.0) / 1e6,
            start_ms: (raw.begin_ns - frame_start_ns) / 1e6,
            render_pass_instances,
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct FrameCounters {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of the frame (its passes' samples passed count every sample).
    pub samples: u32,
    pub passes: Vec<PassCounters>,
    /// Tile traffic of every render pass the frame began (prepasses' targets and the frame).
    pub render_passes: Vec<RenderPassTraffic>,
    /// Every render pass instance the frame began, in submission order.
    pub render_pass_instances: Vec<RenderPassInstance>,
    /// Where the CPU spent the frame's submission (recording, submit, wait).
    pub cpu: CpuPhases,
}

impl FrameCounters {
    pub fn pixels(&self) -> u64 {
        self.width as u64 * self.height as u64
    }

    pub fn pass(&self, name: &str) -> Option<&PassCounters> {
        self.passes.iter().find(|p| p.name == name)
    }

    /// The passes in which the technique drew `draw`, one of its own draw kinds (such as
    /// `VolumeDraw::Volumes`), matched as the `passes` table describes it (the alpha a volume
    /// draw carries does not change it), in the order they ran.
    pub fn drawing<D: DrawKind>(&self, draw: D) -> impl Iterator<Item = &PassCounters> {
        let wanted = draw.describe();
        self.passes.iter().filter(move |p| p.own_draw == Some(wanted))
    }

    /// Sum of fragment shader invocations over all passes (None without pipeline statistics).
    pub fn total_fragment_invocations(&self) -> Option<u64> {
        self.passes.iter().map(|p| p.fragment_invocations).sum()
    }

    pub fn total_samples_passed(&self) -> u64 {
        self.passes.iter().map(|p| p.samples_passed).sum()
    }

    /// The passes' counters summed per render pass instance (`instances::render_pass_sums`).
    pub fn render_pass_sums(&self) -> Vec<RenderPassSums> {
        render_pass_sums(&self.render_pass_instances, &self.passes)
    }

    /// The frame's bytes on a tiler and an immediate-mode GPU: its render pass instances'.
    pub fn bandwidth(&self) -> Bandwidth {
        self.render_pass_sums().iter().map(|s| s.bandwidth).sum()
    }

    /// Each pass's part of the frame's bytes, in `passes` order, the parts summing to
    /// [`Self::bandwidth`]: the pass's own draws (its samples passed x the bytes an
    /// immediate-mode GPU moves per sample of the render pass it drew into), and, in the first
    /// pass that drew into a group of instances (`render_pass_sums`), the group's loads, stores,
    /// clears and resolves. A pass that drew into no render pass (copies only) moves none here.
    pub fn pass_bandwidths(&self) -> Vec<Bandwidth> {
        let mut parts = vec![Bandwidth::default(); self.passes.len()];
        for sum in self.render_pass_sums() {
            let span = sum.first..sum.first + sum.count;
            let group = self.render_pass_instances.get(span.start as usize..span.end as usize).unwrap_or_default();
            let per_sample = group_bytes_per_sample(group);
            let mut fixed = Some(group_fixed_bandwidth(group));
            let drew_in = |pass: &PassCounters| pass.render_pass_instances.iter().any(|i| span.contains(i));
            for (pass, part) in self.passes.iter().zip(&mut parts).filter(|(p, _)| drew_in(p)) {
                part.immediate_bytes += pass.samples_passed * per_sample;
                if let Some(fixed) = fixed.take() {
                    *part = *part + fixed;
                }
            }
        }
        parts
    }

    pub fn total_gpu_ms(&self) -> f64 {
        self.passes.iter().map(|p| p.gpu_ms).sum()
    }

    /// Samples the frame holds: W x H x N.
    pub fn frame_samples(&self) -> u64 {
        self.pixels() * self.samples.max(1) as u64
    }

    /// Samples per pixel of the target `pass` drew into: a pass that began render passes of its
    /// own (a prepass: shadow map, bake, shadow texture) drew into those, at their count (1);
    /// every other pass drew into the frame, at the frame's.
    pub fn pass_samples(&self, pass: &PassCounters) -> u32 {
        let own = self.render_passes.iter().filter(|t| t.pass == pass.name).flat_map(|t| &t.attachments);
        own.map(|a| a.samples).max().unwrap_or(self.samples).max(1)
    }

    /// The pass's samples passed per sample of a frame-sized target at its own sample count,
    /// samples / (W x H x N): the same figure at any frame sample count.
    pub fn samples_per_pixel(&self, pass: &PassCounters) -> f64 {
        pass.samples_passed as f64 / (self.pixels().max(1) * self.pass_samples(pass) as u64) as f64
    }

    /// Samples passed per frame sample, samples / (W x H x N): how many times each sample was
    /// written on average, the same figure at any sample count.
    pub fn overdraw(&self) -> f64 {
        self.total_samples_passed() as f64 / self.frame_samples() as f64
    }
}

/// Groups the instances that measured passes tie together and sums each group's passes. A pass
/// that drew into no render pass (a mip build: copies and blits only) belongs to no group.
fn render_pass_sums(instances: &[RenderPassInstance], passes: &[PassCounters]) -> Vec<RenderPassSums> {
    // group_end[i]: the last instance tied to instance i through some pass.
    let mut group_end: Vec<u32> = (0..instances.len() as u32).collect();
    for pass in passes {
        let (lo, hi) = (pass.render_pass_instances.iter().min(), pass.render_pass_instances.iter().max());
        if let (Some(&lo), Some(&hi)) = (lo, hi.filter(|&&hi| (hi as usize) < instances.len())) {
            for end in &mut group_end[lo as usize..=hi as usize] {
                *end = (*end).max(hi);
            }
        }
    }
    let mut sums = Vec::new();
    let mut first = 0u32;
    while (first as usize) < instances.len() {
        let mut last = group_end[first as usize];
        let mut i = first;
        while i <= last {
            last = last.max(group_end[i as usize]);
            i += 1;
        }
        let inside = |p: &&PassCounters| p.render_pass_instances.iter().any(|&i| (first..=last).contains(&i));
        let members: Vec<&PassCounters> = passes.iter().filter(inside).collect();
        let samples_passed = members.iter().map(|p| p.samples_passed).sum();
        sums.push(RenderPassSums {
            first,
            count: last - first + 1,
            passes: members.iter().map(|p| p.name.clone()).collect(),
            draws: members.iter().map(|p| p.draws).sum(),
            samples_passed,
            fragment_invocations: members.iter().map(|p| p.fragment_invocations).sum(),
            bandwidth: group_bandwidth(&instances[first as usize..=last as usize], samples_passed),
        });
        first = last + 1;
    }
    sums
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::render_pass::AttachmentTraffic;

    fn pass(name: &str, samples_passed: u64) -> PassCounters {
        PassCounters {
            name: name.into(),
            own_draw: None,
            light: None,
            draws: 1,
            commands: 0,
            vertex_invocations: None,
            clipping_primitives: None,
            fragment_invocations: None,
            samples_passed,
            gpu_ms: 0.0,
            start_ms: 0.0,
            render_pass_instances: Vec::new(),
        }
    }

    fn traffic(pass: &str, samples: u32) -> RenderPassTraffic {
        let attachment = AttachmentTraffic {
            attachment: "colour",
            format: "R8G8B8A8_UNORM".into(),
            load_op: "CLEAR".into(),
            store_op: "STORE".into(),
            bytes_loaded: 0,
            bytes_stored: 0,
            bytes_cleared: 0,
            bytes_per_sample: 4,
            transient: false,
            samples,
        };
        RenderPassTraffic { pass: pass.into(), width: 8, height: 8, count: 1, attachments: vec![attachment] }
    }

    #[test]
    fn a_prepass_counts_at_its_own_sample_count_and_frame_passes_at_the_frames() {
        let counters = FrameCounters {
            width: 10,
            height: 10,
            samples: 4,
            passes: vec![pass("shadow texture", 50), pass("scene", 400)],
            render_passes: vec![traffic("shadow texture", 1), traffic("frame", 4)],
            render_pass_instances: Vec::new(),
            cpu: Default::default(),
        };
        let (prepass, scene) = (&counters.passes[0], &counters.passes[1]);
        assert_eq!((counters.pass_samples(prepass), counters.pass_samples(scene)), (1, 4));
        assert_eq!(counters.samples_per_pixel(prepass), 0.5);
        assert_eq!(counters.samples_per_pixel(scene), 1.0);
        assert_eq!(counters.overdraw(), 450.0 / 400.0);
    }

    fn instance(index: u32) -> RenderPassInstance {
        RenderPassInstance { index, width: 4, height: 4, samples: 1, attachments: Vec::new(), passes: Vec::new() }
    }

    fn pass_in(name: &str, instances: &[u32], samples: u64) -> PassCounters {
        PassCounters {
            name: name.into(),
            own_draw: None,
            light: None,
            draws: 1,
            commands: 0,
            vertex_invocations: None,
            clipping_primitives: None,
            fragment_invocations: Some(samples * 2),
            samples_passed: samples,
            gpu_ms: 0.0,
            start_ms: 0.0,
            render_pass_instances: instances.to_vec(),
        }
    }

    #[test]
    fn passes_sum_per_instance_and_a_pass_over_several_instances_joins_them() {
        let instances: Vec<_> = (0..5).map(instance).collect();
        let passes = [
            pass_in("shadow map", &[0], 10),
            pass_in("bake", &[1, 2, 3], 20),
            pass_in("mips", &[], 0),
            pass_in("scene", &[4], 100),
            pass_in("apply", &[4], 7),
        ];
        let sums = render_pass_sums(&instances, &passes);
        let spans: Vec<(u32, u32, u64)> = sums.iter().map(|s| (s.first, s.count, s.samples_passed)).collect();
        assert_eq!(spans, [(0, 1, 10), (1, 3, 20), (4, 1, 107)]);
        assert_eq!(sums[2].passes, ["scene", "apply"]);
        assert_eq!((sums[2].draws, sums[2].fragment_invocations), (2, Some(214)));
    }

    fn cleared_and_stored(width: u32, height: u32) -> RenderPassInstance {
        let bytes = (width * height * 4) as u64;
        let colour =
            AttachmentTraffic { bytes_stored: bytes, bytes_cleared: bytes, ..traffic("x", 1).attachments[0].clone() };
        RenderPassInstance { attachments: vec![colour], width, height, ..instance(0) }
    }

    #[test]
    fn each_passes_bytes_are_its_draws_and_the_first_pass_of_a_group_carries_its_loads_and_stores() {
        // A shadow map (#0), two bakes by one pass (#1, #2), the frame (#3) with two passes in it.
        let instances: Vec<_> =
            (0..4u32).map(|i| RenderPassInstance { index: i, ..cleared_and_stored(4 + i, 4) }).collect();
        let passes = [
            pass_in("shadow map", &[0], 10),
            pass_in("bake", &[1, 2], 20),
            pass_in("mips", &[], 0),
            pass_in("scene", &[3], 100),
            pass_in("apply", &[3], 7),
        ];
        let counters = FrameCounters {
            width: 7,
            height: 4,
            samples: 1,
            passes: passes.to_vec(),
            render_passes: Vec::new(),
            render_pass_instances: instances,
            cpu: Default::default(),
        };
        let parts = counters.pass_bandwidths();
        // Colour RGBA8: cleared and stored once per instance; 8 bytes per passing sample.
        let fixed = |w: u64| w * 4 * 4;
        let expected = [
            Bandwidth { tiler_bytes: fixed(4), immediate_bytes: fixed(4) + 10 * 8 },
            Bandwidth { tiler_bytes: fixed(5) + fixed(6), immediate_bytes: fixed(5) + fixed(6) + 20 * 8 },
            Bandwidth::default(),
            Bandwidth { tiler_bytes: fixed(7), immediate_bytes: fixed(7) + 100 * 8 },
            Bandwidth { tiler_bytes: 0, immediate_bytes: 7 * 8 },
        ];
        assert_eq!(parts, expected);
        assert_eq!(parts.iter().copied().sum::<Bandwidth>(), counters.bandwidth());
    }
}
