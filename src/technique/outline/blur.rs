//! The outline blurred (`--outline-blur R`, seed 003's closing remark on a blur filter): the
//! sharp outline is drawn as a mask into a target of its own, blurred by two 1D box passes of
//! radius R, and blended over the frame in the outline colour. Both paths blur the same mask:
//! the emulated one marks the selection in the mask's alpha and draws the copies where it is 0
//! (`COLOUR_WHERE_ALPHA_ZERO`), the reference one marks a real stencil and draws them where it
//! is `NOT_EQUAL 1`.
//!
//! The mask marks every selected pixel (no depth: an unselected object in front does not hide
//! the selection from its own glow), so on a selection nothing hides it matches the sharp
//! outline exactly.

use std::sync::Arc;

use ash::vk;
use glam::Vec4;

use super::copies::{copy_desc, outline_fixed};
use super::kinds::{OutlineDraw, OutlineKinds, OutlineSet, OutlineTarget};
use crate::error::Result;
use crate::frame::offscreen::{colour_render_pass, colour_stencil_render_pass, Framebuffer, RenderPass};
use crate::frame::targets::choose_depth_format;
use crate::frame::StencilMode;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::{Image, ImageDesc};
use crate::gpu::texture::Sampler;
use crate::gpu::Gpu;
use crate::pipeline::recipes::{self, COLOUR_REPLACE, COLOUR_WHERE_ALPHA_ZERO, OVER_KEEPING_ALPHA, RGB_ONLY};
use crate::pipeline::{BlendState, FixedFunction, PipelineDesc, VertexLayout};
use crate::render::plan::{PlannedPass, SetRole};
use crate::shaders;
use crate::technique::cartoon_shading::cartoon_desc;
use crate::technique::options::OutlineMethod;

/// The sets the blur passes and the apply read.
pub const MASK_SET: SetRole<OutlineSet> = SetRole::Own(OutlineSet::Mask);
pub const BLUR_X_SET: SetRole<OutlineSet> = SetRole::Own(OutlineSet::BlurredAlongX);
pub const BLURRED_SET: SetRole<OutlineSet> = SetRole::Own(OutlineSet::Blurred);

const MASK_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
const BLUR_FORMAT: vk::Format = vk::Format::R8_UNORM;

/// Both windings, no depth: every selected pixel is marked, every copy pixel tested.
fn mask_fixed(blend: BlendState) -> FixedFunction {
    outline_fixed(blend)
}

/// The selected objects as they are (`outline_scale.vert` at scale 1), writing (0, 0, 0, 1);
/// on the reference path also stencil 1.
pub fn mask_selected_desc(stencil: StencilMode) -> PipelineDesc {
    let (name, stencil_state) = match stencil {
        StencilMode::Emulated => ("outline mask: selected", None),
        StencilMode::Reference => ("outline mask: selected (stencil)", Some(recipes::stencil_replace(1))),
    };
    let fixed = FixedFunction { stencil: stencil_state, ..mask_fixed(BlendState::OPAQUE) };
    cartoon_desc(name, shaders::OUTLINE_SCALE_VERT, shaders::CARTOON_COLOUR_FRAG, VertexLayout::POSITION_NORMAL, fixed)
}

/// The copies writing R = 1 where the selection is not marked: alpha 0 (emulated) or stencil
/// not 1 (reference).
pub fn mask_copy_desc(stencil: StencilMode, method: OutlineMethod) -> PipelineDesc {
    match stencil {
        StencilMode::Emulated => {
            copy_desc(method, ["outline mask: copy", "outline mask: scaled copy"], mask_fixed(COLOUR_WHERE_ALPHA_ZERO))
        }
        StencilMode::Reference => {
            let names = ["outline mask: copy (stencil)", "outline mask: scaled copy (stencil)"];
            let mut desc = copy_desc(method, names, mask_fixed(COLOUR_REPLACE));
            desc.fixed.stencil = Some(recipes::stencil_not_equal(1));
            desc
        }
    }
}

/// One 1D box pass over a target.
pub fn blur_desc() -> PipelineDesc {
    PipelineDesc {
        name: "outline blur",
        vertex_shader: shaders::FULLSCREEN_VERT,
        fragment_shader: shaders::OUTLINE_BLUR_FRAG,
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction::FULLSCREEN,
        push_constant_bytes: 16,
    }
}

/// The blurred outline over the frame, frame alpha kept.
pub fn apply_desc() -> PipelineDesc {
    let blend = BlendState { write_mask: RGB_ONLY, ..OVER_KEEPING_ALPHA };
    PipelineDesc {
        name: "outline (blurred)",
        vertex_shader: shaders::FULLSCREEN_VERT,
        fragment_shader: shaders::OUTLINE_BLUR_APPLY_FRAG,
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction { blend, ..FixedFunction::FULLSCREEN },
        push_constant_bytes: 16,
    }
}

/// The push of a blur pass: the step (x or y) and the radius.
pub fn blur_push(along_x: bool, radius: u32) -> Vec4 {
    let (dx, dy) = if along_x { (1.0, 0.0) } else { (0.0, 1.0) };
    Vec4::new(dx, dy, radius as f32, 0.0)
}

/// The table's text for a blur pass's push (the constant it pushes).
fn blur_push_text(along_x: bool, radius: u32) -> String {
    let v = blur_push(along_x, radius);
    let f = crate::render::plan::fmt_f32;
    format!("({}, {}, {}, {})", f(v.x), f(v.y), f(v.z), f(v.w))
}

/// The mask and blur passes, offscreen: they run before the frame's render pass.
pub fn offscreen_passes(stencil: StencilMode, method: OutlineMethod, radius: u32) -> Vec<PlannedPass<OutlineKinds>> {
    let mask = PlannedPass::offscreen(
        "outline mask",
        mask_selected_desc(stencil),
        OutlineDraw::Mask,
        "object transform, mark or outline colour, copy parameters (CartoonPush)",
        OutlineTarget::Mask,
    )
    .or_pipeline(mask_copy_desc(stencil, method))
    .with_sets(&[SetRole::Frame]);
    let blur = |name: &'static str, along_x: bool, source, target| {
        let draw = OutlineDraw::Blur { along_x, radius };
        PlannedPass::offscreen(name, blur_desc(), draw, blur_push_text(along_x, radius), target).with_sets(&[source])
    };
    let blur_x = blur("outline blur x", true, MASK_SET, OutlineTarget::BlurX);
    let blur_y = blur("outline blur y", false, BLUR_X_SET, OutlineTarget::BlurY);
    vec![mask, blur_x, blur_y]
}

/// The blurred outline blended over the frame in `colour` (linear).
pub fn apply_pass(colour: Vec4) -> PlannedPass<OutlineKinds> {
    PlannedPass::full_screen("outline (blurred)", apply_desc(), colour).with_sets(&[BLURRED_SET])
}

/// One offscreen target: its image, and the framebuffer binding it to a render pass.
struct BlurTarget {
    // Field order: the framebuffer goes before the image it refers to.
    framebuffer: Framebuffer,
    image: Image,
}

/// The blur's targets, render passes and descriptor sets, at the frame's size.
pub struct BlurTargets {
    pub extent: vk::Extent2D,
    // Field order: the sets go before the sampler and images they point at, each framebuffer
    // before the images it binds (the stencil last).
    mask_set: DescriptorSet,
    blur_x_set: DescriptorSet,
    blurred_set: DescriptorSet,
    _sampler: Sampler,
    mask: BlurTarget,
    blur_x: BlurTarget,
    blur_y: BlurTarget,
    mask_pass: RenderPass,
    blur_pass: RenderPass,
    /// The reference path's stencil (none emulated).
    _stencil: Option<Image>,
}

fn image(gpu: &Arc<Gpu>, name: &str, format: vk::Format, extent: vk::Extent2D) -> Result<Image> {
    let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
    Image::new(
        gpu,
        &ImageDesc { name, format, extent, usage, aspect: vk::ImageAspectFlags::COLOR, mip_levels: 1, samples: 1 },
    )
}

fn texture(image: &Image, sampler: &Sampler) -> Binding {
    Binding::Texture {
        view: image.view,
        sampler: sampler.raw,
        layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        stages: vk::ShaderStageFlags::FRAGMENT,
    }
}

impl BlurTargets {
    pub fn new(gpu: &Arc<Gpu>, stencil: StencilMode, extent: vk::Extent2D) -> Result<Self> {
        let mask_image = image(gpu, "outline mask", MASK_FORMAT, extent)?;
        let (mask_pass, stencil_image) = match stencil {
            StencilMode::Emulated => {
                (colour_render_pass(gpu, MASK_FORMAT, true, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)?, None)
            }
            StencilMode::Reference => {
                let format = choose_depth_format(gpu, StencilMode::Reference)?;
                let stencil_image = Image::new(
                    gpu,
                    &ImageDesc {
                        name: "outline mask stencil",
                        format,
                        extent,
                        usage: vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                            | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                        aspect: vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL,
                        mip_levels: 1,
                        samples: 1,
                    },
                )?;
                (colour_stencil_render_pass(gpu, MASK_FORMAT, format)?, Some(stencil_image))
            }
        };
        let mut views = vec![mask_image.view];
        views.extend(stencil_image.as_ref().map(|s| s.view));
        let mask =
            BlurTarget { framebuffer: Framebuffer::with_views(gpu, &mask_pass, &views, extent)?, image: mask_image };
        let blur_pass = colour_render_pass(gpu, BLUR_FORMAT, false, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)?;
        let blur_target = |name: &str| -> Result<BlurTarget> {
            let image = image(gpu, name, BLUR_FORMAT, extent)?;
            Ok(BlurTarget { framebuffer: Framebuffer::new(gpu, &blur_pass, image.view, extent)?, image })
        };
        let (blur_x, blur_y) = (blur_target("outline blur x")?, blur_target("outline blur y")?);
        let sampler = Sampler::new(gpu, vk::Filter::NEAREST, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let mask_set = DescriptorSet::new(gpu, &[texture(&mask.image, &sampler)])?;
        let blur_x_set = DescriptorSet::new(gpu, &[texture(&blur_x.image, &sampler)])?;
        let blurred_set = DescriptorSet::new(gpu, &[texture(&blur_y.image, &sampler), texture(&mask.image, &sampler)])?;
        Ok(BlurTargets {
            extent,
            mask_set,
            blur_x_set,
            blurred_set,
            _sampler: sampler,
            mask,
            blur_x,
            blur_y,
            mask_pass,
            blur_pass,
            _stencil: stencil_image,
        })
    }

    /// The render pass of an offscreen target of the blur.
    pub fn render_pass(&self, target: OutlineTarget) -> (vk::RenderPass, usize) {
        match target {
            OutlineTarget::Mask => (self.mask_pass.raw, 1),
            OutlineTarget::BlurX | OutlineTarget::BlurY => (self.blur_pass.raw, 1),
        }
    }

    /// A set of the blur (none for the ramps, which are the scene pass's).
    pub fn set(&self, set: OutlineSet) -> Option<&DescriptorSet> {
        match set {
            OutlineSet::Mask => Some(&self.mask_set),
            OutlineSet::BlurredAlongX => Some(&self.blur_x_set),
            OutlineSet::Blurred => Some(&self.blurred_set),
            OutlineSet::Ramps => None,
        }
    }

    /// The render pass, framebuffer and clear values of an offscreen target of the blur.
    pub fn begin(&self, target: OutlineTarget) -> (&RenderPass, vk::Framebuffer, Vec<vk::ClearValue>) {
        let zero = vk::ClearValue { color: vk::ClearColorValue { float32: [0.0; 4] } };
        let stencil_zero = vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } };
        match target {
            OutlineTarget::Mask => {
                let mut clear = vec![zero];
                if self.mask_pass.attachments.len() > 1 {
                    clear.push(stencil_zero);
                }
                (&self.mask_pass, self.mask.framebuffer.raw, clear)
            }
            OutlineTarget::BlurX => (&self.blur_pass, self.blur_x.framebuffer.raw, vec![]),
            OutlineTarget::BlurY => (&self.blur_pass, self.blur_y.framebuffer.raw, vec![]),
        }
    }
}
