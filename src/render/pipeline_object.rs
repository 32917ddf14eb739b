//! Builds a graphics pipeline from a `pipeline::PipelineDesc`: shaders by file name, an
//! interleaved vertex layout, and the fixed-function data. Viewport and scissor are dynamic.

use std::sync::Arc;

use ash::vk;

use crate::error::{Result, VkContext};
use crate::gpu::live_objects::ObjectKind;
use crate::gpu::memory::sample_count_flags;
use crate::gpu::mobile_profile;
use crate::gpu::Gpu;
use crate::pipeline::{BlendEquation, BlendState, FixedFunction, PipelineDesc, VertexLayout};

/// The attribute descriptions of binding 0 for `layout`, packed in order.
fn attribute_descriptions(layout: &VertexLayout) -> Vec<vk::VertexInputAttributeDescription> {
    let mut offset = 0;
    (0..)
        .zip(layout.attributes)
        .map(|(location, attribute)| {
            let description =
                vk::VertexInputAttributeDescription { location, binding: 0, format: attribute.format(), offset };
            offset += attribute.size();
            description
        })
        .collect()
}

/// Where a pipeline draws: a render pass (any compatible one), the colour attachments of its
/// subpass and their sample count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PipelineTarget {
    pub render_pass: vk::RenderPass,
    pub colour_attachments: usize,
    pub samples: u32,
    /// The lights the forward passes sum (fragment specialization constant 1).
    pub lights: u32,
}

impl PipelineTarget {
    /// A one-sample target (every offscreen prepass).
    pub fn one_sample(render_pass: vk::RenderPass, colour_attachments: usize) -> Self {
        PipelineTarget { render_pass, colour_attachments, samples: 1, lights: 1 }
    }

    /// The same target for a frame of `lights` lights.
    pub fn with_lights(self, lights: usize) -> Self {
        PipelineTarget { lights: lights as u32, ..self }
    }
}

pub struct Pipeline {
    gpu: Arc<Gpu>,
    pub raw: vk::Pipeline,
    pub layout: vk::PipelineLayout,
    /// Descriptor sets in the layout (the frame uniforms are set 0 when present).
    pub set_count: u32,
    /// The render pass it was built for (pipelines are only valid in compatible ones).
    pub render_pass: vk::RenderPass,
    /// Samples per pixel of the render pass's attachments.
    pub samples: u32,
    /// Colour attachments of its subpass.
    colour_attachments: usize,
    /// The light count it was specialised for.
    pub lights: u32,
    /// False for overdraw counters and skinned twins, which borrow their original's layout.
    owns_layout: bool,
    pub desc: PipelineDesc,
    /// The same pipeline for GPU-skinned objects (`with_skinned_twin`), sharing this one's
    /// layout, so binding either keeps the sets bound.
    skinned: Option<Box<Pipeline>>,
}

fn blend_attachment(fixed: &FixedFunction) -> vk::PipelineColorBlendAttachmentState {
    let blend = fixed.blend;
    let colour = blend.colour.unwrap_or(BlendEquation::REPLACE);
    let alpha = blend.alpha.unwrap_or(BlendEquation::REPLACE);
    vk::PipelineColorBlendAttachmentState {
        blend_enable: blend.enabled() as vk::Bool32,
        src_color_blend_factor: colour.src,
        dst_color_blend_factor: colour.dst,
        color_blend_op: colour.op,
        src_alpha_blend_factor: alpha.src,
        dst_alpha_blend_factor: alpha.dst,
        alpha_blend_op: alpha.op,
        color_write_mask: blend.write_mask,
    }
}

impl Pipeline {
    #[cfg(test)]
    pub fn new(
        gpu: &Arc<Gpu>,
        desc: &PipelineDesc,
        render_pass: vk::RenderPass,
        set_layouts: &[vk::DescriptorSetLayout],
    ) -> Result<Self> {
        Self::for_target(gpu, desc, PipelineTarget::one_sample(render_pass, 1), set_layouts)
    }

    /// As `new`, for `target`'s subpass: its colour attachments (0: depth only, as a shadow
    /// map's), each blended as `desc.fixed.blend` says, and its sample count.
    pub fn for_target(
        gpu: &Arc<Gpu>,
        desc: &PipelineDesc,
        target: PipelineTarget,
        set_layouts: &[vk::DescriptorSetLayout],
    ) -> Result<Self> {
        mobile_profile::check_push_constants(desc.name, desc.push_constant_bytes)?;
        let device = gpu.raw();

        let ranges = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            offset: 0,
            size: desc.push_constant_bytes,
        }];
        let layout_info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(set_layouts)
            .push_constant_ranges(if desc.push_constant_bytes > 0 { &ranges } else { &[] });
        // SAFETY: `gpu` holds the device; the set layouts are the caller's, alive for the call;
        // the push-constant range was checked against the profile's limit above.
        let layout = unsafe { device.create_pipeline_layout(&layout_info, None) }.vk("vkCreatePipelineLayout")?;
        gpu.created(ObjectKind::PipelineLayout);
        Self::with_layout(gpu, desc, target, layout, set_layouts.len() as u32, true)
    }

    /// The same pipeline with its fragment stage replaced by an overdraw counter: alpha
    /// `ADD, ONE, ONE` of 1/255 per fragment, colour untouched, every other state (depth,
    /// stencil, culling) kept, so it counts exactly the fragments the original shades. It shares
    /// the original's layout, so the technique's descriptor sets and push constants still fit.
    pub fn overdraw_counter(&self) -> Result<Pipeline> {
        let mut desc = self.desc.clone();
        desc.fragment_shader = crate::shaders::overdraw_counter_for(desc.vertex_shader).ok_or_else(|| {
            crate::error::Error::Internal(format!("no overdraw counter for vertex shader '{}'", desc.vertex_shader))
        })?;
        desc.fixed.blend = BlendState {
            colour: None,
            alpha: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ONE, vk::BlendFactor::ONE)),
            write_mask: vk::ColorComponentFlags::A,
        };
        let target = PipelineTarget {
            render_pass: self.render_pass,
            colour_attachments: 1,
            samples: self.samples,
            lights: self.lights,
        };
        Self::with_layout(&self.gpu, &desc, target, self.layout, self.set_count, false)
    }

    /// This pipeline with its skinned twin built beside it (`PipelineDesc::skinned_twin`), for
    /// the same target and layout: what draws a skinned object skinned on the GPU. Unchanged
    /// when the description has no twin.
    pub fn with_skinned_twin(mut self) -> Result<Self> {
        if let Some(desc) = self.desc.skinned_twin() {
            let target = PipelineTarget {
                render_pass: self.render_pass,
                colour_attachments: self.colour_attachments,
                samples: self.samples,
                lights: self.lights,
            };
            let twin = Self::with_layout(&self.gpu, &desc, target, self.layout, self.set_count, false)?;
            self.skinned = Some(Box::new(twin));
        }
        Ok(self)
    }

    /// The pipeline that draws a skinned object with this one's state: its skinned twin.
    /// `None` when it was built without one.
    pub fn skinned(&self) -> Option<&Pipeline> {
        self.skinned.as_deref()
    }

    fn with_layout(
        gpu: &Arc<Gpu>,
        desc: &PipelineDesc,
        target: PipelineTarget,
        layout: vk::PipelineLayout,
        set_count: u32,
        owns_layout: bool,
    ) -> Result<Self> {
        let PipelineTarget { render_pass, colour_attachments, samples, lights } = target;
        let device = gpu.raw();
        let mut pipeline = Pipeline {
            gpu: gpu.clone(),
            raw: vk::Pipeline::null(),
            layout,
            set_count,
            render_pass,
            samples,
            colour_attachments,
            lights,
            owns_layout,
            desc: desc.clone(),
            skinned: None,
        };

        let vertex_module = ShaderModule::new(gpu, desc.vertex_shader)?;
        let fragment_module = ShaderModule::new(gpu, desc.fragment_shader)?;
        // Fragment specialization constant 0 is the target's sample count, for shaders that
        // read every sample of a multisampled input; 1 the frame's light count, for shaders
        // that sum the lights (a shader without them ignores them).
        let constants: Vec<u8> = [samples as i32, lights as i32].iter().flat_map(|c| c.to_ne_bytes()).collect();
        let entries = [
            vk::SpecializationMapEntry { constant_id: 0, offset: 0, size: 4 },
            vk::SpecializationMapEntry { constant_id: 1, offset: 4, size: 4 },
        ];
        let specialization = vk::SpecializationInfo::default().map_entries(&entries).data(&constants);
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vertex_module.raw)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(fragment_module.raw)
                .name(c"main")
                .specialization_info(&specialization),
        ];

        let layout_desc = desc.vertex_layout;
        let bindings = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: layout_desc.stride(),
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let attributes = attribute_descriptions(&layout_desc);
        let vertex_input = if attributes.is_empty() {
            vk::PipelineVertexInputStateCreateInfo::default()
        } else {
            vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&bindings)
                .vertex_attribute_descriptions(&attributes)
        };

        let fixed = &desc.fixed;
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(fixed.topology);
        let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
        let raster = raster_state(fixed);
        // Rasterised at the target's sample count. No sample shading: `sampleRateShading` is not
        // in the mobile profile, so a shader that needs every sample reads them all itself.
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(sample_count_flags(samples));
        let depth_stencil = depth_stencil_state(fixed);
        let attachments = vec![blend_attachment(fixed); colour_attachments];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);

        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth_stencil)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout)
            .render_pass(render_pass)
            .subpass(0);
        // SAFETY: every state struct `info` points at lives until the call returns; the shader
        // modules are alive (dropped at the end of this function); `layout` is alive (owned by
        // this pipeline or its original) and `render_pass` is the caller's, alive for the call;
        // every vertex format is one Vulkan requires for vertex buffers. On failure `pipeline`
        // is dropped, which destroys the layout it owns.
        let raw = unsafe { device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) }
            .map_err(|(_, result)| result)
            .vk("vkCreateGraphicsPipelines")?;
        pipeline.raw = raw[0];
        gpu.created(ObjectKind::Pipeline);
        Ok(pipeline)
    }
}

/// Filled triangles as `fixed` culls and biases them, lines one pixel wide (no `wideLines` in
/// the mobile profile).
fn raster_state(fixed: &FixedFunction) -> vk::PipelineRasterizationStateCreateInfo<'static> {
    let bias = fixed.raster.depth_bias;
    vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(fixed.raster.cull)
        .front_face(fixed.raster.front_face)
        .line_width(1.0)
        .depth_bias_enable(bias.is_some())
        .depth_bias_constant_factor(bias.map_or(0.0, |b| b.constant))
        .depth_bias_slope_factor(bias.map_or(0.0, |b| b.slope))
}

/// `fixed`'s depth test and write, and its stencil test where it has one (the reference path).
fn depth_stencil_state(fixed: &FixedFunction) -> vk::PipelineDepthStencilStateCreateInfo<'static> {
    let depth_stencil = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(fixed.depth.compare.is_some())
        .depth_write_enable(fixed.depth.write)
        .depth_compare_op(fixed.depth.compare.unwrap_or(vk::CompareOp::ALWAYS));
    match fixed.stencil {
        Some(stencil) => {
            depth_stencil.stencil_test_enable(true).front(stencil.front.to_vk()).back(stencil.back.to_vk())
        }
        None => depth_stencil,
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        // The twin borrows this layout: it goes first.
        self.skinned = None;
        let device = self.gpu.raw();
        // SAFETY: no pending command uses the pipeline (see `Buffer`'s drop). Each layout is
        // destroyed once, by the pipeline that created it: overdraw twins borrow it and leave it.
        unsafe {
            if self.raw != vk::Pipeline::null() {
                device.destroy_pipeline(self.raw, None);
                self.gpu.destroyed(ObjectKind::Pipeline);
            }
            if self.owns_layout {
                device.destroy_pipeline_layout(self.layout, None);
                self.gpu.destroyed(ObjectKind::PipelineLayout);
            }
        }
    }
}

struct ShaderModule<'a> {
    gpu: &'a Gpu,
    raw: vk::ShaderModule,
}

impl<'a> ShaderModule<'a> {
    fn new(gpu: &'a Gpu, shader: crate::shaders::Shader) -> Result<Self> {
        let code = crate::shaders::spirv(shader)?;
        let info = vk::ShaderModuleCreateInfo::default().code(&code);
        // SAFETY: `code` is SPIR-V compiled by shaderc at build time, as u32 words.
        let raw = unsafe { gpu.raw().create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
        gpu.created(ObjectKind::ShaderModule);
        Ok(ShaderModule { gpu, raw })
    }
}

impl Drop for ShaderModule<'_> {
    fn drop(&mut self) {
        // SAFETY: a module is only needed while pipelines are created from it.
        unsafe { self.gpu.raw().destroy_shader_module(self.raw, None) };
        self.gpu.destroyed(ObjectKind::ShaderModule);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::VertexAttribute;

    #[test]
    fn attributes_pack_in_order_at_their_sizes() {
        use VertexAttribute::*;
        let layout = VertexLayout { attributes: &[Vec3, Vec2, F32, U16x4, Vec4] };
        let placed: Vec<_> = attribute_descriptions(&layout).iter().map(|d| (d.location, d.offset, d.format)).collect();
        assert_eq!(
            placed,
            [
                (0, 0, vk::Format::R32G32B32_SFLOAT),
                (1, 12, vk::Format::R32G32_SFLOAT),
                (2, 20, vk::Format::R32_SFLOAT),
                (3, 24, vk::Format::R16G16B16A16_UINT),
                (4, 32, vk::Format::R32G32B32A32_SFLOAT),
            ]
        );
        assert_eq!(layout.stride(), 48);
        assert!(attribute_descriptions(&VertexLayout::NONE).is_empty());
    }
}
