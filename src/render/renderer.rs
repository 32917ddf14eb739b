//! Renders frames: clear, the technique's measured passes inside one render pass (so a
//! tile-based GPU keeps everything on chip), then a copy of the colour target to the CPU (or
//! none: kept on the GPU, or drawn into a swapchain image). One frame at a time by default, or
//! up to `MAX_FRAMES_IN_FLIGHT` in flight, each in a slot of its own (`set_frames_in_flight`).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use image::RgbaImage;

use super::counters::{FrameCounters, PassCounters};
use super::frame_record::PassRecord;
use super::instances::RenderPassInstance;
use super::overdraw::OverdrawPipelines;
use super::recorder::FrameRecorder;
#[cfg(test)]
use super::sample_readback::{self, FrameSamples};
use super::uniforms::{FrameDescriptors, FrameUniforms};
use crate::error::Result;
use crate::frame::render_pass::RenderPassTraffic;
#[cfg(test)]
use crate::frame::StencilMode;
use crate::frame::{image_from_rgba8, FrameTargets};
use crate::gpu::barriers;
use crate::gpu::frame_submission::{CpuPhases, FrameSync, SubmitSlot};
use crate::gpu::memory::Buffer;
use crate::gpu::queries::PassQueryPools;
use crate::gpu::regions;
use crate::gpu::Gpu;
use crate::scene::{JointPalettes, Scene};

/// Measured passes a frame may hold.
pub const MAX_PASSES_PER_FRAME: u32 = 64;

pub struct FrameOutput {
    pub image: RgbaImage,
    pub counters: FrameCounters,
    /// Every measured pass with the labels of the pipelines it bound, in order: what ran.
    pub trace: Vec<(String, Vec<&'static str>)>,
}

/// The swapchain image the next frame is drawn into, and how it is handed over.
#[derive(Debug, Clone, Copy)]
pub struct PresentedFrame {
    /// The acquired image's index in the swapchain the targets are attached to.
    pub index: u32,
    /// Signalled by the acquire: the frame's colour writes wait for it.
    pub acquired: vk::Semaphore,
    /// Signalled when the frame completes: its present waits for it.
    pub finished: vk::Semaphore,
    /// Also copies the presented image into this buffer (a screenshot, sized for the frame at
    /// 4 bytes a pixel), before it is presented.
    pub screenshot: Option<vk::Buffer>,
}

/// What one frame in flight owns until its fence signals: its command buffer and fence, its
/// queries, its uniforms and its read-back buffer.
struct FrameSlot {
    submission: SubmitSlot,
    queries: PassQueryPools,
    frame: FrameDescriptors,
    readback: Buffer,
    /// The frame submitted from this slot, until its results are read.
    pending: Option<PendingFrame>,
}

/// What a submitted frame's results are read with once it completes.
struct PendingFrame {
    passes: Vec<PassRecord>,
    render_passes: Vec<RenderPassTraffic>,
    instances: Vec<RenderPassInstance>,
    cpu: CpuPhases,
    /// Its image was copied into the slot's read-back buffer.
    read_back: bool,
}

/// The most frames a renderer keeps in flight.
pub const MAX_FRAMES_IN_FLIGHT: usize = 3;

pub struct Renderer {
    pub gpu: Arc<Gpu>,
    pub targets: FrameTargets,
    /// The layout of every slot's frame uniforms (set 0 of every pipeline).
    pub frame_layout: vk::DescriptorSetLayout,
    /// One per frame in flight, used in turn.
    slots: Vec<FrameSlot>,
    /// The slot the next frame is recorded in.
    current: usize,
    /// The frame `wait_for_slot` collected from the current slot, returned by the next render.
    collected: Option<FrameOutput>,
    keep_on_gpu: bool,
    /// Heat-map frames: every pipeline of the frame's render pass is replaced by an overdraw
    /// counter, and the colour target's alpha ends up holding fragments shaded per pixel.
    pub count_overdraw: bool,
    /// The stencil aspect's clear value (reference paths only; 0 unless a technique's stencil
    /// test wants its counts to start elsewhere).
    pub stencil_clear: u32,
    overdraw_pipelines: OverdrawPipelines,
    /// Joints of skinned objects' palettes each slot's frame set has room for.
    palette_joints: usize,
    /// A frame has been drawn into the targets (what `read_samples` reads).
    drawn: bool,
    /// Where the next frame goes, when the targets are a swapchain's (`present_next`).
    presented: Option<PresentedFrame>,
}

impl FrameSlot {
    fn new(gpu: &Arc<Gpu>, targets: &FrameTargets, palette_joints: usize) -> Result<Self> {
        let (width, height) = (targets.extent.width, targets.extent.height);
        // A presented frame is never read back (its screenshot goes to the presenter's buffer).
        let readback_size = if targets.presents() { 4 } else { width as u64 * height as u64 * 4 };
        Ok(FrameSlot {
            submission: SubmitSlot::new(gpu)?,
            queries: PassQueryPools::new(gpu, MAX_PASSES_PER_FRAME)?,
            frame: FrameDescriptors::new(gpu, palette_joints)?,
            readback: Buffer::new(
                gpu,
                "frame readback",
                readback_size,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?,
            pending: None,
        })
    }
}

impl Renderer {
    /// A one-sample frame. `colour_feedback`: the colour target is also an input attachment of
    /// its own subpass.
    #[cfg(test)]
    pub fn new(gpu: &Arc<Gpu>, width: u32, height: u32, stencil: StencilMode, colour_feedback: bool) -> Result<Self> {
        Self::with_targets(gpu, FrameTargets::new(gpu, width, height, stencil, colour_feedback)?)
    }

    /// A frame drawn into `targets` (any sample count), one frame at a time
    /// (`set_frames_in_flight` for more).
    #[cfg(test)]
    pub fn with_targets(gpu: &Arc<Gpu>, targets: FrameTargets) -> Result<Self> {
        Self::with_palettes(gpu, targets, 0)
    }

    /// As `with_targets`, with room in every slot's frame set for `palette_joints` joints of
    /// skinned objects' palettes (`scene::JointPalettes::joints`), which a GPU-skinning
    /// technique writes each frame (`write_joint_palettes`).
    pub fn with_palettes(gpu: &Arc<Gpu>, targets: FrameTargets, palette_joints: usize) -> Result<Self> {
        let slot = FrameSlot::new(gpu, &targets, palette_joints)?;
        Ok(Renderer {
            gpu: gpu.clone(),
            frame_layout: slot.frame.layout,
            slots: vec![slot],
            current: 0,
            collected: None,
            keep_on_gpu: targets.presents(),
            count_overdraw: false,
            stencil_clear: 0,
            overdraw_pipelines: OverdrawPipelines::new(targets.render_pass),
            targets,
            palette_joints,
            drawn: false,
            presented: None,
        })
    }

    /// Keeps `frames` frames (1 to `MAX_FRAMES_IN_FLIGHT`) in flight: a frame is submitted
    /// without waiting, and the next one that reuses its slot waits for it; `render` then
    /// returns the results of that frame, `frames` frames earlier. At 1 (the default) each
    /// frame waits for itself and returns its own results. The frames in flight now complete
    /// first.
    pub fn set_frames_in_flight(&mut self, frames: usize) -> Result<()> {
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&frames) {
            return Err(crate::error::Error::InvalidInput(format!(
                "{frames} frames in flight: use 1 to {MAX_FRAMES_IN_FLIGHT}"
            )));
        }
        self.wait_all()?;
        self.slots.truncate(frames);
        while self.slots.len() < frames {
            self.slots.push(FrameSlot::new(&self.gpu, &self.targets, self.palette_joints)?);
        }
        self.current = 0;
        Ok(())
    }

    /// Frames in flight (`set_frames_in_flight`).
    pub fn frames_in_flight(&self) -> usize {
        self.slots.len()
    }

    /// The frame slot the next frame is recorded in: per-frame data a technique writes on the
    /// CPU (posed vertices, volumes) goes in this slot's copy, which no frame in flight reads
    /// once `wait_for_slot` (or the render) waited for it.
    pub fn slot(&self) -> usize {
        self.current
    }

    /// Waits for the frame that last used the next frame's slot, if it is still in flight, and
    /// keeps its results for the next render to return: after it, that slot's per-frame data
    /// may be written. The next render calls it if the caller did not (a presenter calls it
    /// before acquiring an image, whose semaphore the waited frame used).
    pub fn wait_for_slot(&mut self) -> Result<()> {
        if self.collected.is_none() {
            self.collected = self.collect(self.current)?;
        }
        Ok(())
    }

    /// Writes the skinned objects' joint palettes of `scene` into the next frame's slot (its
    /// frame set's binding 1), for vertex stages that skin on the GPU. The slot must be free
    /// (`wait_for_slot`).
    pub fn write_joint_palettes(&mut self, scene: &Scene, palettes: &JointPalettes) -> Result<()> {
        self.slots[self.current].frame.write_palettes(scene, palettes)
    }

    /// Waits for every frame in flight (their results are dropped).
    pub fn wait_all(&mut self) -> Result<()> {
        self.collected = None;
        for index in 0..self.slots.len() {
            self.collect(index)?;
        }
        Ok(())
    }

    /// Draws the next frame into the swapchain image `frame` names (the targets are a
    /// swapchain's: `FrameTargets::presenting`, attached to it).
    pub fn present_next(&mut self, frame: PresentedFrame) -> Result<()> {
        self.targets.select_output(frame.index)?;
        self.presented = Some(frame);
        Ok(())
    }

    /// Leaves each frame on the GPU, in `targets.colour()` (layout TRANSFER_SRC_OPTIMAL) for
    /// the caller to copy (a viewer that cannot draw into its swapchain images): `render`
    /// skips the copy to the CPU and returns an empty 0x0 image. Counters are read back as usual.
    pub fn keep_on_gpu(&mut self, keep: bool) {
        // A presented frame has nothing of the renderer's own to read back.
        self.keep_on_gpu = keep || self.targets.presents();
    }

    /// Every sample of the last frame, before its resolve: for frames whose targets keep their
    /// samples (`RenderOptions.keep_samples`). A one-off pass and copy, never in a timed frame.
    #[cfg(test)]
    pub fn read_samples(&mut self) -> Result<FrameSamples> {
        if !self.drawn {
            return Err(crate::error::Error::InvalidInput("read_samples: no frame has been rendered yet".into()));
        }
        self.wait_all()?;
        sample_readback::read_samples(&self.gpu, &self.targets)
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.targets.extent
    }

    pub fn aspect(&self) -> f32 {
        self.targets.extent.width as f32 / self.targets.extent.height as f32
    }

    /// Renders a frame: `record` draws the technique's passes between the clear and the read-back.
    /// `clear` is the colour target's clear value (alpha included: the counter's start value).
    #[cfg(test)]
    pub fn render(
        &mut self,
        uniforms: &FrameUniforms,
        clear: [f32; 4],
        record: impl FnOnce(&mut FrameRecorder) -> Result<()>,
    ) -> Result<FrameOutput> {
        self.render_with_prepass(uniforms, clear, |_| Ok(()), record)
    }

    /// As `render`, with `prepass` recorded first, outside the frame's render pass: for passes
    /// that render into targets of their own (shadow maps, shadow textures). It begins and ends
    /// its own render passes with `FrameRecorder::begin_render_pass`; its measured passes come
    /// first in the frame's counters.
    ///
    /// With one frame in flight it returns this frame's results. With more, the frame is
    /// submitted without waiting, and it returns those of the frame that last used this frame's
    /// slot (waited for here, or in `wait_for_slot`): no passes for the first frames.
    pub fn render_with_prepass(
        &mut self,
        uniforms: &FrameUniforms,
        clear: [f32; 4],
        prepass: impl FnOnce(&mut FrameRecorder) -> Result<()>,
        record: impl FnOnce(&mut FrameRecorder) -> Result<()>,
    ) -> Result<FrameOutput> {
        self.wait_for_slot()?;
        let completed = self.collected.take();
        let presented = self.presented.take();
        if self.targets.presents() && presented.is_none() {
            return Err(crate::error::Error::Internal(
                "a frame for swapchain images was rendered without an acquired image (present_next)".into(),
            ));
        }
        let sync = FrameSync {
            wait: presented.map(|p| (p.acquired, vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)),
            signal: presented.map(|p| p.finished),
        };
        let index = self.current;
        if self.slots.len() == 1 {
            // The last frame's overdraw pipelines are no longer in use (it was waited for).
            self.overdraw_pipelines.clear();
        }
        let overdraw = self.count_overdraw.then_some(&self.overdraw_pipelines);
        // The overdraw count starts at 0 in alpha.
        let clear = if self.count_overdraw { [clear[0], clear[1], clear[2], 0.0] } else { clear };
        let gpu = self.gpu.clone();
        let device = gpu.raw();
        let extent = self.targets.extent;
        let (keep_on_gpu, stencil_clear) = (self.keep_on_gpu, self.stencil_clear);
        let targets = &self.targets;
        let slot = &mut self.slots[index];
        slot.frame.update(uniforms)?;
        let (queries, readback, frame_set) = (&slot.queries, &slot.readback, slot.frame.set);

        let ((passes, (render_passes, instances)), cpu) = slot.submission.submit(sync, describe_passes, |cmd| {
            queries.reset(cmd);
            let mut recorder = FrameRecorder::new(
                &gpu,
                cmd,
                queries,
                extent,
                frame_set,
                targets.drawn_colour_image(),
                targets.samples(),
            )
            .in_slot(index);
            if let Some(pipelines) = overdraw {
                recorder.count_overdraw(pipelines);
            }
            prepass(&mut recorder)?;
            record_frame_pass(&mut recorder, targets, (clear, stencil_clear), record)?;
            // A technique's fragment shaders may count into a buffer read after the frame.
            barriers::fragment_stores_to_host(device, cmd);
            gpu.counted_commands(recorder.record.commands);
            if let Some(e) = recorder.deferred_error.take() {
                return Err(e);
            }
            let record = std::mem::take(&mut recorder.record);
            let records = (record.passes, (record.render_passes, record.instances));
            if let Some(buffer) = presented.and_then(|p| p.screenshot) {
                super::frame_copy::record_screenshot(device, cmd, targets.output_image(), extent, buffer);
            }
            if !keep_on_gpu {
                record_readback(device, cmd, targets, readback)?;
            }
            Ok(records)
        })?;
        slot.pending = Some(PendingFrame { passes, render_passes, instances, cpu, read_back: !keep_on_gpu });
        self.drawn = true;
        if self.slots.len() == 1 {
            return self
                .collect(index)?
                .ok_or_else(|| crate::error::Error::Internal("a submitted frame had no results".into()));
        }
        self.current = (index + 1) % self.slots.len();
        Ok(completed.unwrap_or_else(|| self.no_results()))
    }

    /// Waits for the frame pending in slot `index`, if any, and reads its results: its image
    /// (unless kept on the GPU) and counters.
    fn collect(&mut self, index: usize) -> Result<Option<FrameOutput>> {
        let slot = &mut self.slots[index];
        let Some(pending) = slot.pending.take() else { return Ok(None) };
        let waited = slot.submission.wait()?.unwrap_or(0.0);
        let extent = self.targets.extent;
        let raw = slot.queries.results(pending.passes.len() as u32)?;
        let frame_start = raw.first().map_or(0.0, |r| r.begin_ns);
        let trace = pending.passes.iter().map(|r| (r.name.clone(), r.pipelines.clone())).collect();
        let passes = pending
            .passes
            .into_iter()
            .zip(&raw)
            .map(|(record, raw)| {
                PassCounters::from_queries(
                    record.name,
                    (record.own_draw, record.light),
                    (record.draws, record.commands),
                    record.instances,
                    raw,
                    frame_start,
                )
            })
            .collect();
        let image = if pending.read_back {
            image_from_rgba8(extent.width, extent.height, slot.readback.read()?.to_vec())?
        } else {
            RgbaImage::new(0, 0)
        };
        // The wait follows the submit (at once with one frame in flight).
        let mut cpu = pending.cpu;
        cpu.wait = (cpu.submit.0 + cpu.submit.1, waited);
        Ok(Some(FrameOutput {
            image,
            counters: FrameCounters {
                width: extent.width,
                height: extent.height,
                samples: self.targets.samples(),
                passes,
                render_passes: pending.render_passes,
                render_pass_instances: pending.instances,
                cpu,
            },
            trace,
        }))
    }

    /// What a render returns while no earlier frame has completed: no image and no passes.
    fn no_results(&self) -> FrameOutput {
        let extent = self.targets.extent;
        FrameOutput {
            image: RgbaImage::new(0, 0),
            counters: FrameCounters {
                width: extent.width,
                height: extent.height,
                samples: self.targets.samples(),
                passes: Vec::new(),
                render_passes: Vec::new(),
                render_pass_instances: Vec::new(),
                cpu: Default::default(),
            },
            trace: Vec::new(),
        }
    }
}

impl Drop for Renderer {
    fn drop(&mut self) {
        // The frames in flight read the targets and the technique's buffers, dropped after.
        for slot in &mut self.slots {
            let _ = slot.submission.wait();
        }
    }
}

/// The frame's render pass: cleared to `clear` (colour) and `stencil_clear` (the reference
/// path's stencil), the technique's passes recorded by `record`.
fn record_frame_pass(
    recorder: &mut FrameRecorder,
    targets: &FrameTargets,
    (clear, stencil_clear): ([f32; 4], u32),
    record: impl FnOnce(&mut FrameRecorder) -> Result<()>,
) -> Result<()> {
    // The resolve target (if any) is not cleared; its value is never read.
    let clear_values = [
        vk::ClearValue { color: vk::ClearColorValue { float32: clear } },
        vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: stencil_clear } },
        vk::ClearValue { color: vk::ClearColorValue { float32: clear } },
    ];
    let attachments = targets.desc.attachments();
    recorder.begin_render_pass(
        targets.render_pass,
        &attachments,
        targets.framebuffer()?,
        targets.extent,
        &clear_values,
    );
    let recorded = record(recorder);
    recorder.end_render_pass();
    recorded
}

/// Copies the finished colour target into the read-back buffer, visible to the host.
fn record_readback(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    targets: &FrameTargets,
    readback: &Buffer,
) -> Result<()> {
    let colour = targets
        .colour()
        .ok_or_else(|| crate::error::Error::Internal("a frame drawn into swapchain images was read back".into()))?;
    // The render pass left the colour target in TRANSFER_SRC_OPTIMAL.
    let region = regions::colour_to_buffer(targets.extent);
    // SAFETY: `cmd` is recording outside the render pass; the colour target and the read-back
    // buffer (sized width x height x 4 for this extent) belong to the renderer, which outlives
    // the submission `submit_frame_and_wait` waits for.
    unsafe {
        device.cmd_copy_image_to_buffer(cmd, colour.raw, vk::ImageLayout::TRANSFER_SRC_OPTIMAL, readback.raw, &[region])
    };
    barriers::transfer_to_host(device, cmd, readback.raw);
    Ok(())
}

/// "the frame's passes: shadow volumes, apply" for a failed submit.
fn describe_passes<R>((passes, _): &(Vec<PassRecord>, R)) -> String {
    let names: Vec<&str> = passes.iter().map(|p| p.name.as_str()).collect();
    format!("the frame's passes: {}", names.join(", "))
}
