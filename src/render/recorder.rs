//! Records one frame's passes. Every logical pass is bracketed by queries, so profiling is a
//! by-product of structure: a technique names its passes and gets their counters back.

use ash::vk;
use bytemuck::Pod;

use super::gpu_mesh::GpuMesh;
use super::instances::RenderPassInstance;
use crate::error::{Error, Result};
use crate::frame::offscreen::RenderPass;
use crate::frame::render_pass::{AttachmentDesc, RenderPassTraffic};
use crate::gpu::barriers;
use crate::gpu::memory::Buffer;
use crate::gpu::queries::PassQueryPools;
use crate::gpu::regions;
use crate::gpu::Gpu;
use crate::render::pipeline_object::Pipeline;

pub(crate) struct PassRecord {
    pub name: String,
    /// What the technique drew in it itself (`DrawKind::describe` of its own draw kind), for
    /// [`FrameCounters::drawing`](super::counters::FrameCounters::drawing).
    pub own_draw: Option<&'static str>,
    /// The light the plan drew the pass for (`PlannedPass::light`).
    pub light: Option<u8>,
    pub draws: u32,
    /// State and draw commands it recorded (binds, pushes, scissors, draws, clears).
    pub commands: u32,
    /// Labels of the pipelines bound in the pass, in first-bound order (the plan test compares
    /// them with the plan).
    pub pipelines: Vec<&'static str>,
    /// The render pass instances its draws went into (`FrameRecorder::instances`).
    pub instances: Vec<u32>,
}

/// Overdraw counters standing in for the technique's pipelines in a heat-map frame, built on
/// first use, keyed by the pipeline they replace; the renderer empties it before each frame.
#[derive(Default)]
pub struct OverdrawPipelines {
    pub(crate) frame_render_pass: vk::RenderPass,
    twins: std::cell::RefCell<std::collections::HashMap<vk::Pipeline, Pipeline>>,
}

impl OverdrawPipelines {
    pub(crate) fn new(frame_render_pass: vk::RenderPass) -> Self {
        OverdrawPipelines { frame_render_pass, twins: Default::default() }
    }

    pub(crate) fn clear(&self) {
        self.twins.borrow_mut().clear();
    }

    /// The counter for `pipeline` (its raw handle), or the pipeline itself when it draws into a
    /// target other than the frame (shadow maps are not part of the frame's overdraw).
    fn substitute(&self, pipeline: &Pipeline) -> Result<vk::Pipeline> {
        if pipeline.render_pass != self.frame_render_pass {
            return Ok(pipeline.raw);
        }
        let mut twins = self.twins.borrow_mut();
        if let Some(twin) = twins.get(&pipeline.raw) {
            return Ok(twin.raw);
        }
        let twin = pipeline.overdraw_counter()?;
        let raw = twin.raw;
        twins.insert(pipeline.raw, twin);
        Ok(raw)
    }
}

/// One indexed draw of the buffers bound last ([`FrameRecorder::draw_bound`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoundDraw {
    pub first_index: u32,
    pub index_count: u32,
    /// Added to every index: where the draw's vertices start in the vertex buffer.
    pub vertex_offset: i32,
    /// The one instance's `gl_InstanceIndex`.
    pub first_instance: u32,
}

/// Records one frame into `cmd`.
///
/// Soundness of its raw Vulkan calls: `cmd` is recording (inside `submit_and_wait`'s closure),
/// and every handle given to it (pipelines, buffers, sets, framebuffers) belongs to an object
/// that outlives the frame, which `submit_and_wait` waits for. What depends on the order of
/// recording (one render pass open at a time, a pipeline bound before a draw) is the
/// techniques' to keep; the validation layer checks it in every test.
pub struct FrameRecorder<'a> {
    gpu: &'a Gpu,
    /// Set for heat-map frames: every bind is replaced by its overdraw counter.
    overdraw: Option<&'a OverdrawPipelines>,
    /// First error from building an overdraw counter (binds cannot fail otherwise).
    pub(crate) deferred_error: Option<Error>,
    pub cmd: vk::CommandBuffer,
    queries: &'a PassQueryPools,
    pub(crate) passes: Vec<PassRecord>,
    /// What each render pass begun moves to and from main memory on a tile-based GPU.
    pub(crate) render_passes: Vec<RenderPassTraffic>,
    /// Every render pass instance begun, in order, with the measured passes drawn into it.
    pub(crate) instances: Vec<RenderPassInstance>,
    /// The render pass instance open now, if any.
    open_instance: Option<u32>,
    open: bool,
    pub extent: vk::Extent2D,
    frame_set: vk::DescriptorSet,
    /// The frame's colour target (read back as an input attachment by feedback passes).
    colour_image: vk::Image,
    /// A pass narrowed the scissor: it is put back to the whole frame when the pass ends.
    scissor_narrowed: bool,
    /// The open render pass was begun outside a measured pass (the frame's) and carries the
    /// label "frame", closed with it.
    frame_label_open: bool,
    /// Samples per pixel of the frame's render pass.
    frame_samples: u32,
    /// The frame slot this frame is recorded in (`Renderer::slot`): which copy of per-frame
    /// data its draws read.
    slot: usize,
    /// The vertex and index buffers bound last (binding 0), so that a draw of the geometry
    /// bound already binds nothing: lavapipe allocates every command it records, and a port's
    /// driver validates each. Every bind into `cmd` goes through this recorder.
    bound_vertices: Option<vk::Buffer>,
    bound_indices: Option<vk::Buffer>,
    /// State and draw commands recorded so far (`Activity::commands`).
    pub(crate) commands: u64,
}

impl<'a> FrameRecorder<'a> {
    pub(crate) fn new(
        gpu: &'a Gpu,
        cmd: vk::CommandBuffer,
        queries: &'a PassQueryPools,
        extent: vk::Extent2D,
        frame_set: vk::DescriptorSet,
        colour_image: vk::Image,
        frame_samples: u32,
    ) -> Self {
        FrameRecorder {
            gpu,
            overdraw: None,
            deferred_error: None,
            cmd,
            queries,
            passes: Vec::new(),
            render_passes: Vec::new(),
            instances: Vec::new(),
            open_instance: None,
            open: false,
            extent,
            frame_set,
            colour_image,
            scissor_narrowed: false,
            frame_label_open: false,
            frame_samples,
            slot: 0,
            bound_vertices: None,
            bound_indices: None,
            commands: 0,
        }
    }

    /// The recorder of a frame in frame slot `slot`.
    pub(crate) fn in_slot(mut self, slot: usize) -> Self {
        self.slot = slot;
        self
    }

    /// The frame slot this frame is recorded in: draws bind that slot's copy of data written
    /// every frame (`Renderer::slot`).
    pub fn slot(&self) -> usize {
        self.slot
    }

    /// Samples per pixel of the frame's render pass.
    pub fn frame_samples(&self) -> u32 {
        self.frame_samples
    }

    /// The frame's uniforms (camera, light), bound at set 0 of pipelines that use them.
    pub fn frame_set(&self) -> vk::DescriptorSet {
        self.frame_set
    }

    /// Notes that the open pass bound `pipeline`.
    fn trace_bind(&mut self, pipeline: &Pipeline) {
        if let Some(pass) = self.passes.last_mut().filter(|_| self.open) {
            if !pass.pipelines.contains(&pipeline.desc.name) {
                pass.pipelines.push(pipeline.desc.name);
            }
        }
    }

    pub(crate) fn count_overdraw(&mut self, pipelines: &'a OverdrawPipelines) {
        self.overdraw = Some(pipelines);
    }

    fn pipeline_to_bind(&mut self, pipeline: &Pipeline) -> vk::Pipeline {
        match self.overdraw.map(|o| o.substitute(pipeline)) {
            None => pipeline.raw,
            Some(Ok(raw)) => raw,
            Some(Err(e)) => {
                self.deferred_error.get_or_insert(e);
                pipeline.raw
            }
        }
    }

    /// Records `body` as one measured pass called `name`.
    pub fn pass(&mut self, name: &str, body: impl FnOnce(&mut Self) -> Result<()>) -> Result<()> {
        if self.open {
            return Err(Error::Internal(format!("pass '{name}' begun inside another pass")));
        }
        let index = self.passes.len() as u32;
        if index >= self.queries.capacity() {
            return Err(Error::Internal(format!(
                "pass '{name}': a frame holds at most {} measured passes",
                self.queries.capacity()
            )));
        }
        // A pass recorded inside an open render pass draws into it (the frame's render pass).
        let instances: Vec<u32> = self.open_instance.into_iter().collect();
        if let Some(instance) = self.open_instance.and_then(|i| self.instances.get_mut(i as usize)) {
            instance.passes.push(name.to_owned());
        }
        self.passes.push(PassRecord {
            name: name.to_owned(),
            own_draw: None,
            light: None,
            draws: 0,
            commands: 0,
            pipelines: Vec::new(),
            instances,
        });
        self.open = true;
        // The label brackets the pass's queries, so a tool reading labels sees the same extent
        // the counters measure.
        self.gpu.begin_label(self.cmd, name);
        self.queries.begin(self.cmd, index);
        let result = body(self);
        if std::mem::take(&mut self.scissor_narrowed) {
            self.record_scissor(vk::Rect2D { offset: vk::Offset2D::default(), extent: self.extent });
        }
        self.queries.end(self.cmd, index);
        self.gpu.end_label(self.cmd);
        self.open = false;
        result
    }

    /// Draws from here to the end of the current measured pass land only inside `rect` (the
    /// frame's render pass; the whole frame again after the pass).
    pub fn set_scissor(&mut self, rect: vk::Rect2D) {
        self.scissor_narrowed = true;
        self.record_scissor(rect);
    }

    fn record_scissor(&mut self, rect: vk::Rect2D) {
        self.count_commands(1);
        // SAFETY: see the note on `FrameRecorder`; every pipeline has a dynamic scissor.
        unsafe { self.gpu.raw().cmd_set_scissor(self.cmd, 0, &[rect]) };
    }

    /// Begins a render pass on a target of the technique's own (outside the frame's render
    /// pass, in `Renderer::render_with_prepass`), with viewport and scissor covering `extent`;
    /// its tile traffic is counted for the measured pass recording it, so it must be begun (and
    /// ended) inside one: otherwise the frame fails with an error naming the mistake.
    pub fn begin_offscreen_pass(
        &mut self,
        render_pass: &RenderPass,
        framebuffer: vk::Framebuffer,
        extent: vk::Extent2D,
        clear_values: &[vk::ClearValue],
    ) {
        let whole = vk::Rect2D { offset: vk::Offset2D::default(), extent };
        self.begin_offscreen_pass_in(render_pass, framebuffer, extent, whole, clear_values);
    }

    /// As [`Self::begin_offscreen_pass`] with a render area `area` inside the framebuffer (the
    /// atlas page's re-baked tiles): only that area is loaded, cleared and stored, and the
    /// scissor keeps draws inside it (the viewport still spans `extent`).
    pub fn begin_offscreen_pass_in(
        &mut self,
        render_pass: &RenderPass,
        framebuffer: vk::Framebuffer,
        extent: vk::Extent2D,
        area: vk::Rect2D,
        clear_values: &[vk::ClearValue],
    ) {
        if !self.open {
            self.deferred_error.get_or_insert(Error::Internal(
                "an offscreen render pass was begun outside a measured pass (its traffic and counters \
                 would belong to no pass)"
                    .into(),
            ));
        }
        let target = (render_pass.raw, framebuffer, extent);
        self.begin_render_pass_in(target, &render_pass.attachments, area, clear_values);
    }

    /// Begins `render_pass`, whose attachments `attachments` describes (for the tile-traffic
    /// count: under the open measured pass, else under "frame"), with viewport and scissor
    /// covering `extent`.
    pub(crate) fn begin_render_pass(
        &mut self,
        render_pass: vk::RenderPass,
        attachments: &[AttachmentDesc],
        framebuffer: vk::Framebuffer,
        extent: vk::Extent2D,
        clear_values: &[vk::ClearValue],
    ) {
        let whole = vk::Rect2D { offset: vk::Offset2D::default(), extent };
        self.begin_render_pass_in((render_pass, framebuffer, extent), attachments, whole, clear_values);
    }

    /// Begins `target` (render pass, framebuffer, its extent) over the render area `area`; the
    /// tile traffic and the instance count the area.
    fn begin_render_pass_in(
        &mut self,
        (render_pass, framebuffer, framebuffer_extent): (vk::RenderPass, vk::Framebuffer, vk::Extent2D),
        attachments: &[AttachmentDesc],
        area: vk::Rect2D,
        clear_values: &[vk::ClearValue],
    ) {
        let extent = area.extent;
        let pass = match (self.open, self.passes.last()) {
            (true, Some(p)) => p.name.clone(),
            _ => "frame".to_owned(),
        };
        let traffic = RenderPassTraffic {
            pass,
            width: extent.width,
            height: extent.height,
            count: 1,
            attachments: attachments.iter().map(|a| a.tile_traffic(extent.width, extent.height)).collect(),
        };
        let same = |t: &&mut RenderPassTraffic| {
            (&t.pass, t.width, t.height, &t.attachments)
                == (&traffic.pass, traffic.width, traffic.height, &traffic.attachments)
        };
        let index = self.instances.len() as u32;
        let mut instance = RenderPassInstance {
            index,
            width: extent.width,
            height: extent.height,
            samples: attachments.iter().map(|a| a.samples).max().unwrap_or(1),
            attachments: traffic.attachments.clone(),
            passes: Vec::new(),
        };
        // A render pass begun inside a measured pass (a prepass) holds that pass's draws.
        if let Some(pass) = self.passes.last_mut().filter(|_| self.open) {
            pass.instances.push(index);
            instance.passes.push(pass.name.clone());
        }
        self.instances.push(instance);
        self.open_instance = Some(index);
        match self.render_passes.iter_mut().find(same) {
            Some(alike) => alike.count += 1,
            None => self.render_passes.push(traffic),
        }
        if !self.open {
            // The frame's render pass: its measured passes label themselves inside it.
            self.gpu.begin_label(self.cmd, "frame");
            self.frame_label_open = true;
        }
        let device = self.gpu.raw();
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(render_pass)
            .framebuffer(framebuffer)
            .render_area(area)
            // One clear value per attachment: callers may pass one for an attachment this
            // variant lacks (the resolve target at one sample), which Vulkan would ignore.
            .clear_values(&clear_values[..clear_values.len().min(attachments.len())]);
        let viewport = regions::full_viewport(framebuffer_extent);
        // SAFETY: see the note on `FrameRecorder`; `render_pass` and `framebuffer` come from
        // the same targets (so are compatible), and `clear_values` covers their attachments.
        unsafe {
            device.cmd_begin_render_pass(self.cmd, &begin, vk::SubpassContents::INLINE);
            device.cmd_set_viewport(self.cmd, 0, &[viewport]);
            device.cmd_set_scissor(self.cmd, 0, &[area]);
        }
        self.count_commands(2);
    }

    pub fn end_render_pass(&mut self) {
        self.open_instance = None;
        // SAFETY: see the note on `FrameRecorder`.
        unsafe { self.gpu.raw().cmd_end_render_pass(self.cmd) };
        if std::mem::take(&mut self.frame_label_open) {
            self.gpu.end_label(self.cmd);
        }
    }

    /// The GPU, for technique code that records commands the recorder has no helper for (not
    /// binds: the recorder keeps what is bound, and skips binding it again).
    pub fn device(&self) -> &ash::Device {
        self.gpu.raw()
    }

    /// Counts a draw recorded: in the open pass's draws, and as a command.
    fn count_draw(&mut self) {
        self.count_commands(1);
        if let Some(pass) = self.passes.last_mut() {
            pass.draws += 1;
        }
    }

    /// Counts `count` state and draw commands recorded: the frame's, and the open pass's.
    fn count_commands(&mut self, count: u64) {
        self.commands += count;
        if let Some(pass) = self.passes.last_mut().filter(|_| self.open) {
            pass.commands += count as u32;
        }
    }

    /// Binds a pipeline, and the frame's uniforms when its layout has a set for them.
    pub fn bind(&mut self, pipeline: &Pipeline) {
        self.trace_bind(pipeline);
        let raw = self.pipeline_to_bind(pipeline);
        let device = self.gpu.raw();
        // SAFETY: see the note on `FrameRecorder`; `raw` is the pipeline or its overdraw twin,
        // which shares its layout, and set 0 of a layout with sets is the frame uniforms'.
        unsafe {
            device.cmd_bind_pipeline(self.cmd, vk::PipelineBindPoint::GRAPHICS, raw);
            if pipeline.set_count > 0 {
                device.cmd_bind_descriptor_sets(
                    self.cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    pipeline.layout,
                    0,
                    &[self.frame_set],
                    &[],
                );
            }
        }
        self.count_commands(1 + u64::from(pipeline.set_count > 0));
    }

    /// Binds a pipeline with descriptor sets of the technique's own (not the frame uniforms).
    pub fn bind_with_sets(&mut self, pipeline: &Pipeline, sets: &[vk::DescriptorSet]) {
        self.trace_bind(pipeline);
        let raw = self.pipeline_to_bind(pipeline);
        let device = self.gpu.raw();
        // SAFETY: see the note on `FrameRecorder`; `raw` is the pipeline or its overdraw twin,
        // which shares its layout, and the technique's sets were made for that layout.
        unsafe {
            device.cmd_bind_pipeline(self.cmd, vk::PipelineBindPoint::GRAPHICS, raw);
            if !sets.is_empty() {
                device.cmd_bind_descriptor_sets(
                    self.cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    pipeline.layout,
                    0,
                    sets,
                    &[],
                );
            }
        }
        self.count_commands(1 + u64::from(!sets.is_empty()));
    }

    /// Binds descriptor sets from `first` on, for the pipeline bound last (`pipeline`'s layout).
    pub fn bind_sets(&mut self, pipeline: &Pipeline, first: u32, sets: &[vk::DescriptorSet]) {
        self.count_commands(1);
        // SAFETY: see the note on `FrameRecorder`; the caller's sets were made for `pipeline`'s
        // layout, which the pipeline bound last shares.
        unsafe {
            self.gpu.raw().cmd_bind_descriptor_sets(
                self.cmd,
                vk::PipelineBindPoint::GRAPHICS,
                pipeline.layout,
                first,
                sets,
                &[],
            )
        };
    }

    /// Binds a material's set at `MATERIAL_SET` for the pipeline bound last (`pipeline`).
    pub fn bind_material(&mut self, pipeline: &Pipeline, set: vk::DescriptorSet) {
        self.bind_sets(pipeline, super::materials::MATERIAL_SET, &[set]);
    }

    /// Sets the whole stencil aspect of the frame's depth-stencil target to `value`, inside the
    /// frame's render pass (which clears it to 0): for a reference path whose stencil test
    /// wants another starting value.
    pub fn clear_stencil(&mut self, value: u32) {
        let attachment = vk::ClearAttachment {
            aspect_mask: vk::ImageAspectFlags::STENCIL,
            color_attachment: 0,
            clear_value: vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: value } },
        };
        let rect = vk::ClearRect {
            rect: vk::Rect2D { offset: vk::Offset2D::default(), extent: self.extent },
            base_array_layer: 0,
            layer_count: 1,
        };
        // SAFETY: see the note on `FrameRecorder`; the recorder is inside the frame's render
        // pass (callers clear the stencil only on the reference path, whose target has a stencil
        // aspect), and `rect` is the frame's extent, one layer.
        unsafe { self.gpu.raw().cmd_clear_attachments(self.cmd, &[attachment], &[rect]) };
        self.count_commands(1);
    }

    /// Sets the stencil to `value` inside `rect` (the frame's render pass, reference paths): the
    /// per-light clear of Doom 3's and Ogre's loops, in the light's scissor.
    pub fn clear_stencil_in(&mut self, value: u32, rect: vk::Rect2D) {
        let attachment = vk::ClearAttachment {
            aspect_mask: vk::ImageAspectFlags::STENCIL,
            color_attachment: 0,
            clear_value: vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: value } },
        };
        let rect = vk::ClearRect { rect, base_array_layer: 0, layer_count: 1 };
        if rect.rect.extent.width == 0 || rect.rect.extent.height == 0 {
            return;
        }
        // SAFETY: see the note on `FrameRecorder`; as `clear_stencil`, with `rect` inside the
        // frame (callers clamp it) and not empty (checked above).
        unsafe { self.gpu.raw().cmd_clear_attachments(self.cmd, &[attachment], &[rect]) };
        self.count_commands(1);
    }

    /// Fills mips 1.. of a colour image from its mip 0 (in TRANSFER_DST_OPTIMAL) with linear
    /// blits, leaving every mip sampled (SHADER_READ_ONLY_OPTIMAL); the old contents of mips 1..
    /// are dropped.
    pub fn build_mips(&mut self, image: vk::Image, side: u32, mip_levels: u32) {
        if mip_levels > 1 {
            barriers::upload_destination(self.gpu.raw(), self.cmd, image, 1..mip_levels);
        }
        crate::gpu::texture::record_mip_chain(self.gpu, self.cmd, image, side, side, mip_levels);
    }

    /// As [`Self::build_mips`] for a `width` x `height` image whose mip 0 was left ready for
    /// sampling by the render pass that wrote it (the atlas page).
    pub fn build_mips_from_sampled(&mut self, image: vk::Image, width: u32, height: u32, mip_levels: u32) {
        crate::gpu::texture::record_mip_chain_from_sampled(self.gpu, self.cmd, image, width, height, mip_levels);
    }

    /// Viewport and scissor both `rect` until the render pass ends (a tile of an atlas page).
    pub fn set_viewport_rect(&mut self, rect: vk::Rect2D) {
        let viewport = vk::Viewport {
            x: rect.offset.x as f32,
            y: rect.offset.y as f32,
            width: rect.extent.width as f32,
            height: rect.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: see the note on `FrameRecorder`; every pipeline has a dynamic viewport.
        unsafe { self.gpu.raw().cmd_set_viewport(self.cmd, 0, &[viewport]) };
        self.count_commands(1);
        self.set_scissor(rect);
    }

    /// Makes earlier colour writes of this subpass visible to input-attachment reads of the
    /// following draws (`barriers::colour_feedback`).
    pub fn colour_feedback_barrier(&mut self) {
        barriers::colour_feedback(self.gpu.raw(), self.cmd, self.colour_image);
    }

    /// Pushes `value` as the pipeline's push constants (vertex and fragment stages, offset 0).
    pub fn push<T: Pod>(&mut self, pipeline: &Pipeline, value: &T) {
        let bytes = bytemuck::bytes_of(value);
        if bytes.len() as u32 > pipeline.desc.push_constant_bytes || bytes.len() % 4 != 0 {
            self.deferred_error.get_or_insert(Error::Internal(format!(
                "pipeline '{}': {} bytes of push constants for a {}-byte range",
                pipeline.desc.name,
                bytes.len(),
                pipeline.desc.push_constant_bytes
            )));
            return;
        }
        self.count_commands(1);
        // SAFETY: see the note on `FrameRecorder`; the bytes fit the layout's one range (offset
        // 0, vertex and fragment stages, checked just above) and are a whole number of words.
        unsafe {
            self.gpu.raw().cmd_push_constants(
                self.cmd,
                pipeline.layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                bytes,
            )
        };
    }

    /// Draws `mesh` as this frame's slot holds it (a skinned mesh's posed copy).
    pub fn draw_mesh(&mut self, mesh: &GpuMesh) {
        self.draw_mesh_vertices(mesh, mesh.indices(), mesh.first_index, mesh.index_count);
    }

    /// `mesh`'s vertices as this frame's slot holds them, drawn with indices `first_index..
    /// first_index + index_count` of `indices`: the mesh's own, or a simplified set over the
    /// same vertices (counted from the mesh's first vertex, wherever its buffer holds it).
    pub fn draw_mesh_vertices(&mut self, mesh: &GpuMesh, indices: &Buffer, first_index: u32, index_count: u32) {
        let (vertices, vertex_offset) = mesh.vertices_in(self.slot);
        self.bind_indexed(vertices, indices);
        self.draw_bound(BoundDraw { first_index, index_count, vertex_offset, first_instance: 0 });
    }

    pub fn draw_indexed(&mut self, vertices: &Buffer, indices: &Buffer, index_count: u32) {
        self.draw_indexed_range(vertices, indices, 0, index_count);
    }

    /// [`FrameRecorder::draw_indexed`] of `index_count` indices from index `first_index` on.
    pub fn draw_indexed_range(&mut self, vertices: &Buffer, indices: &Buffer, first_index: u32, index_count: u32) {
        if index_count == 0 {
            return;
        }
        self.bind_indexed(vertices, indices);
        self.draw_bound_range(first_index, index_count);
    }

    /// Binds `vertices` and `indices` (32-bit) for the [`FrameRecorder::draw_bound_range`]
    /// calls that follow: several ranges of one geometry drawn with one binding.
    pub fn bind_indexed(&mut self, vertices: &Buffer, indices: &Buffer) {
        self.bind_vertices(vertices);
        self.bind_indices(indices);
    }

    /// Binds `vertices` for the draws that follow (binding 0), unless they are bound already.
    pub fn bind_vertices(&mut self, vertices: &Buffer) {
        if self.bound_vertices.replace(vertices.raw) == Some(vertices.raw) {
            return;
        }
        // SAFETY: see the note on `FrameRecorder`; the buffer outlives the frame (its owner keeps
        // it until its fence).
        unsafe { self.gpu.raw().cmd_bind_vertex_buffers(self.cmd, 0, &[vertices.raw], &[0]) };
        self.count_commands(1);
    }

    /// Binds `indices` (32-bit) for the indexed draws that follow, unless they are bound already.
    pub fn bind_indices(&mut self, indices: &Buffer) {
        if self.bound_indices.replace(indices.raw) == Some(indices.raw) {
            return;
        }
        // SAFETY: as `bind_vertices`.
        unsafe { self.gpu.raw().cmd_bind_index_buffer(self.cmd, indices.raw, 0, vk::IndexType::UINT32) };
        self.count_commands(1);
    }

    /// Draws indices `first_index..first_index + index_count` of the buffers
    /// [`FrameRecorder::bind_indexed`] bound last.
    pub fn draw_bound_range(&mut self, first_index: u32, index_count: u32) {
        self.draw_bound(BoundDraw { first_index, index_count, vertex_offset: 0, first_instance: 0 });
    }

    /// One instance of `draw`'s indices of the buffers bound last, their vertices from
    /// `vertex_offset` on, `gl_InstanceIndex` its `first_instance` (a value the vertex shader
    /// reads, with no push between draws).
    pub fn draw_bound(&mut self, draw: BoundDraw) {
        if draw.index_count == 0 {
            return;
        }
        // SAFETY: see the note on `FrameRecorder`; the indices were checked against their
        // vertices when the mesh was built (the glTF loader refuses any out of range), and the
        // range lies inside the index buffer bound, its vertices from `vertex_offset` on inside
        // the vertex buffer bound (their owners sized them).
        unsafe {
            self.gpu.raw().cmd_draw_indexed(
                self.cmd,
                draw.index_count,
                1,
                draw.first_index,
                draw.vertex_offset,
                draw.first_instance,
            )
        };
        self.count_draw();
    }

    /// `instances` instances of indices `first_index..first_index + index_count` of `indices`,
    /// with no vertex buffer: the vertex shader pulls its data by index (`gl_VertexIndex`).
    pub fn draw_indexed_instances(&mut self, indices: &Buffer, first_index: u32, index_count: u32, instances: u32) {
        if index_count == 0 || instances == 0 {
            return;
        }
        self.bind_indices(indices);
        // SAFETY: see the note on `FrameRecorder`; the range lies inside the index buffer (its
        // owner sized it), and the vertex shader reads no vertex buffer.
        unsafe { self.gpu.raw().cmd_draw_indexed(self.cmd, index_count, instances, first_index, 0, 0) };
        self.count_draw();
    }

    pub fn draw_vertices(&mut self, vertices: &Buffer, vertex_count: u32) {
        if vertex_count == 0 {
            return;
        }
        self.bind_vertices(vertices);
        // SAFETY: see the note on `FrameRecorder`; `vertex_count` is the caller's count of the
        // vertices it uploaded to `vertices`.
        unsafe { self.gpu.raw().cmd_draw(self.cmd, vertex_count, 1, 0, 0) };
        self.count_draw();
    }

    /// One full-screen triangle (`shaders/fullscreen.vert`).
    /// `instances` instances of `vertices` vertices made by the vertex shader (no vertex
    /// buffer), the first instance index `first_instance`.
    pub fn draw_instances(&mut self, vertices: u32, instances: u32, first_instance: u32) {
        // SAFETY: see the note on `FrameRecorder`; the vertex shader makes its vertices from
        // gl_VertexIndex and gl_InstanceIndex, with no vertex buffer.
        unsafe { self.gpu.raw().cmd_draw(self.cmd, vertices, instances, 0, first_instance) };
        self.count_draw();
    }

    pub fn draw_fullscreen(&mut self) {
        // SAFETY: see the note on `FrameRecorder`; the vertex shader makes the three vertices
        // from gl_VertexIndex, with no vertex buffer.
        unsafe { self.gpu.raw().cmd_draw(self.cmd, 3, 1, 0, 0) };
        self.count_draw();
    }
}
