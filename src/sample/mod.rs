//! The samples' base class (`examples/*.rs`, docs/porting.md): what every sample needs and no
//! technique is about, as Sascha Willems' `VulkanExampleBase` is for his samples.
//!
//! A sample writes its render pass, its pipelines (each blend state named, its formula in a
//! comment) and its draws in order, in plain ash. This base gives it:
//! - the device (the library's [`Gpu`], validation as the caller chose) and one built-in scene
//!   on the GPU: its meshes, materials and frame uniforms, as the engine uploads them, so that a
//!   sample's lit pass is the engine's lit pass, to the bit;
//! - the frame's two attachments: colour `R8G8B8A8_SRGB` (alpha kept: the emulated stencil) and
//!   depth, with a stencil aspect only for the `--stencil` reference;
//! - a pipeline from its parts ([`PipelineParts`]), shaders by their file name in `shaders/`;
//! - one submission that records the frame and reads the colour attachment back;
//! - its `main` ([`run`]): the two options, `--out FILE.png` and `--stencil`, and the PNG.
//!
//! Every Vulkan object a sample makes through the base is destroyed with it.

use std::cell::RefCell;
use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use image::RgbaImage;

use crate::error::{Error, Result, VkContext};
use crate::frame::targets::choose_depth_format;
use crate::frame::StencilMode;
use crate::gpu::barriers;
use crate::gpu::commands::submit_and_wait;
use crate::gpu::memory::{Buffer, Image, ImageDesc};
use crate::gpu::Gpu;
use crate::render::gpu_mesh::GpuScene;
use crate::render::object_push::{draw_order, object_push};
use crate::render::uniforms::{FrameDescriptors, FrameUniforms};
use crate::scene::{builtin_scene, Scene, SceneObject};

pub use ash;

mod cartoon;
mod command_line;
mod sets;
mod shadow_atlas;
pub use cartoon::SmoothCopy;
pub use command_line::run;
pub use sets::ExtraSet;
pub use shadow_atlas::{ShadowAtlas, MAP_FORMAT, PAGE_FORMAT};
mod ground;
pub use ground::Ground;
mod selection;
pub use selection::linear_colour;

/// The colour attachment's format: the engine's frame format.
pub const COLOUR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

/// Bytes of push constants every sample pipeline may use: the mobile profile's whole 128.
pub const PUSH_BYTES: u32 = 128;

/// What a sample's vertex stage reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VertexInput {
    /// Nothing: a full-screen triangle made from the vertex index (`fullscreen.vert`).
    None,
    /// The scene meshes' vertices (`scene_vertex.glsl`: position, normal, UV0, UV1, COLOR_0).
    Scene,
    /// One `vec4` position per vertex at location 0 (a volume's doubled vertices: w = 1 on the
    /// caster, w = 0 pushed away from the light).
    Position4,
    /// Position and normal (`vec3` each) at locations 0 and 1: a welded mesh with smooth
    /// normals (`cartoon_extrude.vert`'s copies).
    PositionNormal,
    /// The shadow techniques' vertex (`atlas_vertex.glsl`): position, normal, atlas UV, UV0,
    /// UV1, COLOR_0 ([`ShadowAtlas`]'s meshes).
    Atlas,
    /// An ink quad's corner (`cartoon_ink.vert`): both ends of its edge and a third point
    /// (`vec3` each), and the corner (`vec2`), at locations 0 to 3.
    Ink,
}

/// A graphics pipeline's parts: the state a technique chooses, the rest fixed (one subpass,
/// one colour attachment, one sample, dynamic viewport and scissor, counter-clockwise front
/// faces, triangle lists).
#[derive(Clone, Copy)]
pub struct PipelineParts<'a> {
    pub render_pass: vk::RenderPass,
    pub vertex_shader: &'a str,
    pub fragment_shader: &'a str,
    pub vertex_input: VertexInput,
    pub cull: vk::CullModeFlags,
    /// The depth test's compare op; `None`: no depth test.
    pub depth_test: Option<vk::CompareOp>,
    pub depth_write: bool,
    pub blend: vk::PipelineColorBlendAttachmentState,
    /// Front and back stencil state (the reference path only); `None`: no stencil test.
    pub stencil: Option<(vk::StencilOpState, vk::StencilOpState)>,
}

impl Default for PipelineParts<'_> {
    fn default() -> Self {
        PipelineParts {
            render_pass: vk::RenderPass::null(),
            vertex_shader: "fullscreen.vert",
            fragment_shader: "solid.frag",
            vertex_input: VertexInput::None,
            cull: vk::CullModeFlags::NONE,
            depth_test: None,
            depth_write: false,
            blend: replace(vk::ColorComponentFlags::RGBA),
            stencil: None,
        }
    }
}

/// Blending off: the fragment replaces the channels in `write`.
pub fn replace(write: vk::ColorComponentFlags) -> vk::PipelineColorBlendAttachmentState {
    vk::PipelineColorBlendAttachmentState::default().blend_enable(false).color_write_mask(write)
}

/// `result = src * src_factor (op) dst * dst_factor`, the same for colour and alpha, writing
/// the channels in `write`.
pub fn blend(
    op: vk::BlendOp,
    src_factor: vk::BlendFactor,
    dst_factor: vk::BlendFactor,
    write: vk::ColorComponentFlags,
) -> vk::PipelineColorBlendAttachmentState {
    vk::PipelineColorBlendAttachmentState::default()
        .blend_enable(true)
        .color_blend_op(op)
        .src_color_blend_factor(src_factor)
        .dst_color_blend_factor(dst_factor)
        .alpha_blend_op(op)
        .src_alpha_blend_factor(src_factor)
        .dst_alpha_blend_factor(dst_factor)
        .color_write_mask(write)
}

/// A stencil face that always passes and does `op` where the depth test passes.
pub fn stencil_face(compare: vk::CompareOp, reference: u32, pass: vk::StencilOp) -> vk::StencilOpState {
    vk::StencilOpState {
        fail_op: vk::StencilOp::KEEP,
        pass_op: pass,
        depth_fail_op: vk::StencilOp::KEEP,
        compare_op: compare,
        compare_mask: 0xff,
        write_mask: 0xff,
        reference,
    }
}

/// An object the base destroys with itself.
enum Owned {
    RenderPass(vk::RenderPass),
    Framebuffer(vk::Framebuffer),
    Pipeline(vk::Pipeline),
}

/// The device, the scene on it and the frame's attachments (module docs).
pub struct SampleBase {
    pub scene: Scene,
    pub extent: vk::Extent2D,
    /// The frame has a real stencil (the `--stencil` reference).
    pub stencil: bool,
    pub depth_format: vk::Format,
    /// Set 0 (the frame's uniforms) and set 1 (a material), [`PUSH_BYTES`] of push constants for
    /// the vertex and fragment stages: every sample pipeline's layout.
    pub layout: vk::PipelineLayout,
    owned: RefCell<Vec<Owned>>,
    /// The render passes made here whose subpass has no colour attachment (a shadow map's):
    /// their pipelines have no blend attachment.
    depth_only: RefCell<Vec<vk::RenderPass>>,
    colour: Image,
    depth: Image,
    gpu_scene: GpuScene,
    frame: FrameDescriptors,
    // Last: everything above is destroyed while the device lives.
    gpu: Arc<Gpu>,
}

impl SampleBase {
    /// Built-in scene `scene` at `width` x `height` on `gpu`, with a stencil aspect in the depth
    /// attachment when `stencil`.
    pub fn new(gpu: &Arc<Gpu>, scene: &str, width: u32, height: u32, stencil: bool) -> Result<Self> {
        if width == 0 || height == 0 {
            return Err(Error::InvalidInput(format!("a frame of {width}x{height} has no pixel")));
        }
        let scene = builtin_scene(scene)?;
        let extent = vk::Extent2D { width, height };
        let mode = if stencil { StencilMode::Reference } else { StencilMode::Emulated };
        let depth_format = choose_depth_format(gpu, mode)?;
        let colour = Image::new(
            gpu,
            &ImageDesc {
                name: "sample colour",
                format: COLOUR_FORMAT,
                extent,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
                aspect: vk::ImageAspectFlags::COLOR,
                mip_levels: 1,
                samples: 1,
            },
        )?;
        let depth_aspect = if stencil {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        } else {
            vk::ImageAspectFlags::DEPTH
        };
        let depth = Image::new(
            gpu,
            &ImageDesc {
                name: "sample depth",
                format: depth_format,
                extent,
                usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                aspect: depth_aspect,
                mip_levels: 1,
                samples: 1,
            },
        )?;
        let gpu_scene = GpuScene::upload(gpu, &scene)?;
        let mut frame = FrameDescriptors::new(gpu, 1)?;
        frame.update(&FrameUniforms::for_scene(&scene, width as f32 / height as f32))?;
        let set_layouts = [frame.layout, gpu_scene.materials.layout()];
        let push = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT)
            .size(PUSH_BYTES)];
        let info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts).push_constant_ranges(&push);
        // SAFETY: the device is alive; both set layouts are (their owners are fields of the base).
        let layout = unsafe { gpu.raw().create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?;
        Ok(SampleBase {
            scene,
            extent,
            stencil,
            depth_format,
            layout,
            owned: RefCell::new(Vec::new()),
            depth_only: RefCell::new(Vec::new()),
            colour,
            depth,
            gpu_scene,
            frame,
            gpu: gpu.clone(),
        })
    }

    pub fn device(&self) -> &ash::Device {
        self.gpu.raw()
    }

    /// A render pass from `info`, destroyed with the base.
    pub fn create_render_pass(&self, info: &vk::RenderPassCreateInfo) -> Result<vk::RenderPass> {
        // SAFETY: the device is alive; `info`'s arrays are borrowed for the call.
        let pass = unsafe { self.device().create_render_pass(info, None) }.vk("vkCreateRenderPass")?;
        self.owned.borrow_mut().push(Owned::RenderPass(pass));
        // SAFETY: a non-null `info.p_subpasses` points at `subpass_count` descriptions (the
        // builder's slice, borrowed for the call).
        let first = (info.subpass_count > 0 && !info.p_subpasses.is_null()).then(|| unsafe { &*info.p_subpasses });
        if first.is_some_and(|s| s.color_attachment_count == 0) {
            self.depth_only.borrow_mut().push(pass);
        }
        Ok(pass)
    }

    /// The framebuffer of the frame's colour and depth attachments (in that order) for
    /// `render_pass`, destroyed with the base.
    pub fn create_framebuffer(&self, render_pass: vk::RenderPass) -> Result<vk::Framebuffer> {
        let views = [self.colour.view, self.depth.view];
        let info = vk::FramebufferCreateInfo::default()
            .render_pass(render_pass)
            .attachments(&views)
            .width(self.extent.width)
            .height(self.extent.height)
            .layers(1);
        // SAFETY: the device, the render pass and both views are alive.
        let framebuffer = unsafe { self.device().create_framebuffer(&info, None) }.vk("vkCreateFramebuffer")?;
        self.owned.borrow_mut().push(Owned::Framebuffer(framebuffer));
        Ok(framebuffer)
    }

    /// A pipeline from its parts, destroyed with the base.
    pub fn pipeline(&self, parts: &PipelineParts) -> Result<vk::Pipeline> {
        self.pipeline_in(self.layout, parts)
    }

    /// A pipeline from its parts with another `layout` than the base's (one with more sets:
    /// [`ExtraSet`]), destroyed with the base.
    pub fn pipeline_in(&self, layout: vk::PipelineLayout, parts: &PipelineParts) -> Result<vk::Pipeline> {
        self.pipeline_biased(layout, parts, None)
    }

    /// [`SampleBase::pipeline_in`] with a depth bias `(constant, slope)` when `bias` is given
    /// ([`SampleBase::pipeline_with_depth_bias`]).
    fn pipeline_biased(
        &self,
        layout: vk::PipelineLayout,
        parts: &PipelineParts,
        bias: Option<(f32, f32)>,
    ) -> Result<vk::Pipeline> {
        let device = self.device();
        let modules = [self.shader_module(parts.vertex_shader)?, self.shader_module(parts.fragment_shader)?];
        let result = self.pipeline_with(layout, parts, bias, modules);
        for module in modules {
            // SAFETY: the pipeline (made or not) no longer needs its modules.
            unsafe { device.destroy_shader_module(module, None) };
        }
        let pipeline = result?;
        self.owned.borrow_mut().push(Owned::Pipeline(pipeline));
        Ok(pipeline)
    }

    fn shader_module(&self, file: &str) -> Result<vk::ShaderModule> {
        let shader = crate::shaders::by_file(file)?;
        let words = crate::shaders::spirv(shader)?;
        // SAFETY: the device is alive; `words` is SPIR-V compiled by build.rs.
        unsafe { self.device().create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&words), None) }
            .vk("vkCreateShaderModule")
    }

    fn pipeline_with(
        &self,
        layout: vk::PipelineLayout,
        parts: &PipelineParts,
        bias: Option<(f32, f32)>,
        [vertex, fragment]: [vk::ShaderModule; 2],
    ) -> Result<vk::Pipeline> {
        const MAIN: &CStr = c"main";
        let stages = [
            vk::PipelineShaderStageCreateInfo::default().stage(vk::ShaderStageFlags::VERTEX).module(vertex).name(MAIN),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(fragment)
                .name(MAIN),
        ];
        let (bindings, attributes) = vertex_layout(parts.vertex_input);
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&bindings)
            .vertex_attribute_descriptions(&attributes);
        let assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(parts.cull)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .depth_bias_enable(bias.is_some())
            .depth_bias_constant_factor(bias.map_or(0.0, |(constant, _)| constant))
            .depth_bias_slope_factor(bias.map_or(0.0, |(_, slope)| slope))
            .line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let (front, back) = parts.stencil.unwrap_or_default();
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(parts.depth_test.is_some())
            .depth_compare_op(parts.depth_test.unwrap_or(vk::CompareOp::ALWAYS))
            .depth_write_enable(parts.depth_write)
            .stencil_test_enable(parts.stencil.is_some())
            .front(front)
            .back(back);
        let attachments = [parts.blend];
        let colour_attachments = if self.depth_only.borrow().contains(&parts.render_pass) { 0 } else { 1 };
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachments[..colour_attachments]);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout)
            .render_pass(parts.render_pass)
            .subpass(0);
        // SAFETY: every handle in `info` is alive and its arrays outlive the call.
        let created = unsafe { self.device().create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
        match created {
            Ok(pipelines) => Ok(pipelines[0]),
            Err((_, code)) => Err(code).vk("vkCreateGraphicsPipelines"),
        }
    }

    /// Viewport and scissor over the whole frame.
    pub fn whole_frame(&self, cmd: vk::CommandBuffer) {
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: self.extent.width as f32,
            height: self.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        let scissor = vk::Rect2D { offset: vk::Offset2D::default(), extent: self.extent };
        // SAFETY: `cmd` is recording; every sample pipeline has a dynamic viewport and scissor.
        unsafe {
            self.device().cmd_set_viewport(cmd, 0, &[viewport]);
            self.device().cmd_set_scissor(cmd, 0, &[scissor]);
        }
    }

    /// Pushes `bytes` (at most [`PUSH_BYTES`]) for the vertex and fragment stages.
    pub fn push(&self, cmd: vk::CommandBuffer, bytes: &[u8]) {
        // SAFETY: `cmd` is recording; the layout's one range covers both stages and 128 bytes.
        unsafe {
            self.device().cmd_push_constants(
                cmd,
                self.layout,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                0,
                bytes,
            )
        };
    }

    /// Draws every object `which` accepts with the bound pipeline (a [`VertexInput::Scene`]
    /// one), in the engine's order (opaque in scene order, then blended back to front), each
    /// with its material (set 1) and its push: transform, base colour and `alpha`, the alpha
    /// the draw writes (the emulated stencil's value).
    pub fn draw_objects(&self, cmd: vk::CommandBuffer, alpha: f32, which: impl Fn(&SceneObject) -> bool) {
        let device = self.device();
        // SAFETY: `cmd` is recording inside a render pass with a scene pipeline bound; every
        // buffer and set bound is a field of the base, alive until it is dropped.
        unsafe {
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout,
                0,
                &[self.frame.set],
                &[],
            );
        }
        for index in draw_order(&self.scene) {
            let object = &self.scene.objects[index];
            let Some(mesh) = self.gpu_scene.meshes.get(object.mesh) else { continue };
            if !which(object) {
                continue;
            }
            let material = self.gpu_scene.materials.set(object.material);
            self.push(cmd, bytemuck::bytes_of(&object_push(&self.scene, object, alpha)));
            let (vertices, vertex_offset) = mesh.vertices_in(0);
            // SAFETY: as above.
            unsafe {
                device.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, self.layout, 1, &[material], &[]);
                device.cmd_bind_vertex_buffers(cmd, 0, &[vertices.raw], &[0]);
                device.cmd_bind_index_buffer(cmd, mesh.indices().raw, 0, vk::IndexType::UINT32);
                device.cmd_draw_indexed(cmd, mesh.index_count, 1, mesh.first_index, vertex_offset, 0);
            }
        }
    }

    /// Binds set 0 (the frame's uniforms) alone, for pipelines that draw no material.
    pub fn bind_frame_uniforms(&self, cmd: vk::CommandBuffer) {
        // SAFETY: `cmd` is recording; the set is a field of the base.
        unsafe {
            self.device().cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout,
                0,
                &[self.frame.set],
                &[],
            )
        };
    }

    /// A vertex buffer holding `data`, kept alive by the caller.
    pub fn vertex_buffer<T: bytemuck::Pod>(&self, name: &str, data: &[T]) -> Result<SampleBuffer> {
        let usage = vk::BufferUsageFlags::VERTEX_BUFFER | vk::BufferUsageFlags::INDEX_BUFFER;
        Ok(SampleBuffer(Buffer::with_data(&self.gpu, name, data, usage)?))
    }

    /// Records `record` (which must end the colour attachment in `TRANSFER_SRC_OPTIMAL`: the
    /// render pass's final layout), then copies the colour attachment out, submits, waits and
    /// returns the frame, alpha kept.
    pub fn render(&self, record: impl FnOnce(vk::CommandBuffer) -> Result<()>) -> Result<RgbaImage> {
        let (width, height) = (self.extent.width, self.extent.height);
        let bytes = width as u64 * height as u64 * 4;
        let readback = Buffer::new(
            &self.gpu,
            "sample read-back",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        submit_and_wait(&self.gpu, |cmd| {
            record(cmd)?;
            let region = vk::BufferImageCopy::default()
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: 1,
                })
                .image_extent(vk::Extent3D { width, height, depth: 1 });
            // SAFETY: the render pass left the colour image in TRANSFER_SRC_OPTIMAL and made its
            // writes available to transfers (its outgoing dependency); the buffer is large enough.
            unsafe {
                self.device().cmd_copy_image_to_buffer(
                    cmd,
                    self.colour.raw,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    readback.raw,
                    &[region],
                )
            };
            barriers::transfer_to_host(self.device(), cmd, readback.raw);
            Ok(())
        })?;
        crate::frame::readback::image_from_rgba8(width, height, readback.read()?.to_vec())
    }

    /// The scene's primary light in `object`'s own space: `xyz` its position (w = 1) or the
    /// direction it travels (w = 0), as the engine's volume builder computes it.
    pub fn light_in_object_space(&self, object: &SceneObject) -> glam::Vec4 {
        let inverse = object.transform.inverse();
        match self.scene.light() {
            crate::scene::Light::Directional { direction } => inverse.transform_vector3(direction).extend(0.0),
            crate::scene::Light::Point { position } => inverse.transform_point3(position).extend(1.0),
        }
    }

    /// Whether the camera's eye or near plane lies in the shadow of a caster: z-pass counts
    /// wrong there (a volume's walls behind the near plane are never drawn), z-fail does not.
    pub fn camera_in_a_volume(&self) -> bool {
        let (casters, _) = crate::technique::shadow_volume::prepare_casters(&self.scene);
        let aspect = self.extent.width as f32 / self.extent.height as f32;
        crate::technique::shadow_volume::casters::camera_inside_volume(&self.scene, &casters, aspect)
    }

    /// `object`'s mesh with coincident vertices merged (the engine's casters' weld): positions
    /// and triangles over them, wound counter-clockwise seen from outside.
    pub fn welded_mesh(&self, object: &SceneObject) -> Result<(Vec<glam::Vec3>, Vec<[u32; 3]>)> {
        let mesh = &self.scene.meshes[object.mesh];
        let welded = crate::mesh::weld::weld_by_position(
            &mesh.name,
            &mesh.data.positions,
            &mesh.data.indices,
            crate::mesh::caster::WELD_EPSILON,
        )?;
        let triangles = welded.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
        Ok((welded.positions, triangles))
    }
}

/// A buffer a sample made through the base (vertex or index data).
pub struct SampleBuffer(Buffer);

impl SampleBuffer {
    pub fn raw(&self) -> vk::Buffer {
        self.0.raw
    }
}

impl Drop for SampleBase {
    fn drop(&mut self) {
        let device = self.gpu.raw();
        // SAFETY: every submission was waited for (`render` waits); nothing the base made is
        // in use, and each object is destroyed once.
        unsafe {
            let _ = device.device_wait_idle();
            for owned in self.owned.borrow_mut().drain(..).rev() {
                match owned {
                    Owned::RenderPass(pass) => device.destroy_render_pass(pass, None),
                    Owned::Framebuffer(framebuffer) => device.destroy_framebuffer(framebuffer, None),
                    Owned::Pipeline(pipeline) => device.destroy_pipeline(pipeline, None),
                }
            }
            device.destroy_pipeline_layout(self.layout, None);
        }
    }
}

/// The vertex bindings and attributes of `input`.
fn vertex_layout(
    input: VertexInput,
) -> (Vec<vk::VertexInputBindingDescription>, Vec<vk::VertexInputAttributeDescription>) {
    let attribute =
        |location, format, offset| vk::VertexInputAttributeDescription { location, binding: 0, format, offset };
    let binding = |stride| {
        vec![vk::VertexInputBindingDescription { binding: 0, stride, input_rate: vk::VertexInputRate::VERTEX }]
    };
    match input {
        VertexInput::None => (Vec::new(), Vec::new()),
        VertexInput::Position4 => (binding(16), vec![attribute(0, vk::Format::R32G32B32A32_SFLOAT, 0)]),
        VertexInput::PositionNormal => (
            binding(24),
            vec![attribute(0, vk::Format::R32G32B32_SFLOAT, 0), attribute(1, vk::Format::R32G32B32_SFLOAT, 12)],
        ),
        VertexInput::Ink => (
            binding(44),
            vec![
                attribute(0, vk::Format::R32G32B32_SFLOAT, 0),
                attribute(1, vk::Format::R32G32B32_SFLOAT, 12),
                attribute(2, vk::Format::R32G32B32_SFLOAT, 24),
                attribute(3, vk::Format::R32G32_SFLOAT, 36),
            ],
        ),
        VertexInput::Atlas => (
            binding(64),
            vec![
                attribute(0, vk::Format::R32G32B32_SFLOAT, 0),
                attribute(1, vk::Format::R32G32B32_SFLOAT, 12),
                attribute(2, vk::Format::R32G32_SFLOAT, 24),
                attribute(3, vk::Format::R32G32_SFLOAT, 32),
                attribute(4, vk::Format::R32G32_SFLOAT, 40),
                attribute(5, vk::Format::R32G32B32A32_SFLOAT, 48),
            ],
        ),
        VertexInput::Scene => (
            binding(std::mem::size_of::<crate::render::gpu_mesh::SceneVertex>() as u32),
            vec![
                attribute(0, vk::Format::R32G32B32_SFLOAT, 0),
                attribute(1, vk::Format::R32G32B32_SFLOAT, 12),
                attribute(2, vk::Format::R32G32_SFLOAT, 24),
                attribute(3, vk::Format::R32G32_SFLOAT, 32),
                attribute(4, vk::Format::R32G32B32A32_SFLOAT, 40),
            ],
        ),
    }
}
