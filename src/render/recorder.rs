//! Records one frame's passes. Every logical pass is bracketed by queries, so profiling is a
//! by-product of structure: a technique names its passes and gets their counters back. The
//! calls here record commands; what they did is noted in a `FrameRecord` (`frame_record`).

use ash::vk;
use bytemuck::Pod;

use super::frame_record::FrameRecord;
use super::gpu_mesh::GpuMesh;
use super::overdraw::OverdrawPipelines;
use crate::error::{Error, Result};
use crate::frame::offscreen::RenderPass;
use crate::frame::render_pass::AttachmentDesc;
use crate::gpu::barriers;
use crate::gpu::memory::Buffer;
use crate::gpu::queries::PassQueryPools;
use crate::gpu::regions;
use crate::gpu::Gpu;
use crate::render::pipeline_object::Pipeline;

/// One `vkCmdDrawIndexed` of the buffers bound last ([`FrameRecorder::draw_indexed`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct IndexedDraw {
    pub index_count: u32,
    pub instance_count: u32,
    pub first_index: u32,
    /// Added to every index: where the draw's vertices start in the vertex buffer.
    pub vertex_offset: i32,
    /// The first instance's `gl_InstanceIndex` (a value the vertex shader reads, with no push
    /// between draws).
    pub first_instance: u32,
}

impl IndexedDraw {
    /// One instance of indices `first_index..first_index + index_count`, from vertex 0.
    pub fn range(first_index: u32, index_count: u32) -> Self {
        IndexedDraw { index_count, instance_count: 1, first_index, vertex_offset: 0, first_instance: 0 }
    }
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
    /// The passes, render passes and commands recorded so far.
    pub(crate) record: FrameRecord,
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
            record: FrameRecord::default(),
            extent,
            frame_set,
            colour_image,
            scissor_narrowed: false,
            frame_label_open: false,
            frame_samples,
            slot: 0,
            bound_vertices: None,
            bound_indices: None,
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
        if self.record.pass_open() {
            return Err(Error::Internal(format!("pass '{name}' begun inside another pass")));
        }
        let index = self.record.passes.len() as u32;
        if index >= self.queries.capacity() {
            return Err(Error::Internal(format!(
                "pass '{name}': a frame holds at most {} measured passes",
                self.queries.capacity()
            )));
        }
        self.record.begin_pass(name);
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
        self.record.end_pass();
        result
    }

    /// Draws from here to the end of the current measured pass land only inside `rect` (the
    /// frame's render pass; the whole frame again after the pass).
    pub fn set_scissor(&mut self, rect: vk::Rect2D) {
        self.scissor_narrowed = true;
        self.record_scissor(rect);
    }

    fn record_scissor(&mut self, rect: vk::Rect2D) {
        self.record.count_commands(1);
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
        if !self.record.pass_open() {
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
        self.record.begin_render_pass(attachments, (area.extent.width, area.extent.height));
        if !self.record.pass_open() {
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
        self.record.count_commands(2);
    }

    pub fn end_render_pass(&mut self) {
        self.record.end_render_pass();
        // SAFETY: see the note on `FrameRecorder`.
        unsafe { self.gpu.raw().cmd_end_render_pass(self.cmd) };
        if std::mem::take(&mut self.frame_label_open) {
            self.gpu.end_label(self.cmd);
        }
    }

    /// The GPU, for technique code that records commands the recorder has no helper for (not
    /// binds: the recorder keeps what is bound, and skips binding it again).
    #[cfg(test)]
    pub fn device(&self) -> &ash::Device {
        self.gpu.raw()
    }

    /// Binds a pipeline, and the frame's uniforms when its layout has a set for them.
    pub fn bind(&mut self, pipeline: &Pipeline) {
        self.record.bound(pipeline.desc.name);
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
        self.record.count_commands(1 + u64::from(pipeline.set_count > 0));
    }

    /// Binds a pipeline with descriptor sets of the technique's own (not the frame uniforms).
    pub fn bind_with_sets(&mut self, pipeline: &Pipeline, sets: &[vk::DescriptorSet]) {
        self.record.bound(pipeline.desc.name);
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
        self.record.count_commands(1 + u64::from(!sets.is_empty()));
    }

    /// Binds descriptor sets from `first` on, for the pipeline bound last (`pipeline`'s layout).
    pub fn bind_sets(&mut self, pipeline: &Pipeline, first: u32, sets: &[vk::DescriptorSet]) {
        self.record.count_commands(1);
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
        self.record.count_commands(1);
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
        self.record.count_commands(1);
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
        self.record.count_commands(1);
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
        self.record.count_commands(1);
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
        let (vertices, vertex_offset) = mesh.vertices_in(self.slot);
        self.bind_indexed(vertices, mesh.indices());
        self.draw_indexed(IndexedDraw { vertex_offset, ..IndexedDraw::range(mesh.first_index, mesh.index_count) });
    }

    /// Binds `vertices` and `indices` (32-bit) for the [`FrameRecorder::draw_indexed`] calls
    /// that follow: several ranges of one geometry drawn with one binding.
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
        self.record.count_commands(1);
    }

    /// Binds `indices` (32-bit) for the indexed draws that follow, unless they are bound already.
    pub fn bind_indices(&mut self, indices: &Buffer) {
        if self.bound_indices.replace(indices.raw) == Some(indices.raw) {
            return;
        }
        // SAFETY: as `bind_vertices`.
        unsafe { self.gpu.raw().cmd_bind_index_buffer(self.cmd, indices.raw, 0, vk::IndexType::UINT32) };
        self.record.count_commands(1);
    }

    /// `vkCmdDrawIndexed` of the index buffer bound last ([`FrameRecorder::bind_indices`]),
    /// over the vertex buffer bound last where the vertex shader reads one (else it pulls its
    /// data by `gl_VertexIndex`); nothing is recorded for no indices or no instances.
    pub fn draw_indexed(&mut self, draw: IndexedDraw) {
        if draw.index_count == 0 || draw.instance_count == 0 {
            return;
        }
        // SAFETY: see the note on `FrameRecorder`; the indices were checked against their
        // vertices when the mesh was built (the glTF loader refuses any out of range), and the
        // range lies inside the index buffer bound, its vertices from `vertex_offset` on inside
        // the vertex buffer bound, or none read (their owners sized them).
        unsafe {
            self.gpu.raw().cmd_draw_indexed(
                self.cmd,
                draw.index_count,
                draw.instance_count,
                draw.first_index,
                draw.vertex_offset,
                draw.first_instance,
            )
        };
        self.record.count_draw();
    }

    /// `vkCmdDraw`: `instance_count` instances of `vertex_count` vertices, of the vertex buffer
    /// bound last ([`FrameRecorder::bind_vertices`]) or made by the vertex shader from
    /// `gl_VertexIndex` and `gl_InstanceIndex` (three: one full-screen triangle,
    /// `shaders/fullscreen.vert`).
    pub fn draw(&mut self, vertex_count: u32, instance_count: u32, first_vertex: u32, first_instance: u32) {
        // SAFETY: see the note on `FrameRecorder`; the vertices lie inside the vertex buffer
        // bound (the caller's count of those it uploaded), or the vertex shader reads none.
        unsafe { self.gpu.raw().cmd_draw(self.cmd, vertex_count, instance_count, first_vertex, first_instance) };
        self.record.count_draw();
    }
}
