//! Render-texture shadows (seed 001): the casters drawn in one flat shade into a small texture
//! from the light (orthographic along a directional light, perspective from a point light),
//! then looked up by the receivers through the same light projection. Memory bounds the
//! texture's size, so the shadow's edges show its texels; a caster leaving the light's frustum
//! would be cut, so the frustum is fitted to the casters' posed bounds every frame.
//!
//! Frame:
//! 1. prepass "shadow texture" (its own render pass, 128x128 RGBA8, cleared to 1): every caster
//!    (GPU-skinned) written with colour F/255, opaque, no depth: overlaps write the same value,
//!    so nothing can darken twice. Stored and left SHADER_READ_ONLY_OPTIMAL.
//! 2. scene: lit objects (GPU-skinned).
//! 3. "shadow texture receive": the receivers drawn again, depth LESS_OR_EQUAL with the planar
//!    bias, each pixel's factor read from the texture (1 outside it), colour blend
//!    `ADD, ZERO, SRC_COLOR`.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3, Vec4};

use super::{
    caster_bounds, light_reaches_plane, lit_descs, receiver_plane, stats, PlanarFrame, ReceiverPlane, SceneMeshes,
    SHADOW_BIAS,
};
use crate::error::Result;
use crate::frame::offscreen::{colour_render_pass, Framebuffer, RenderPass};
use crate::frame::StencilMode;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::{Image, ImageDesc};
use crate::gpu::texture::Sampler;
use crate::gpu::Gpu;
use crate::pipeline::{
    BlendEquation, BlendState, DepthState, FixedFunction, Pipeline, PipelineDesc, RasterState, VertexLayout,
};
use crate::render::{FrameUniforms, Renderer};
use crate::scene::{Light, Scene};
use crate::technique::lit::{ObjectPush, OBJECT_PUSH_BYTES};

/// Side of the shadow texture (small on purpose: what a phone can spare).
pub const SHADOW_TEXTURE_SIZE: u32 = 128;
const SHADOW_TEXTURE_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// Mirrors `ReceivePush` in `shaders/planar_texture_receive.vert` (128 bytes: the profile's limit).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ReceivePush {
    model: Mat4,
    light_view_proj: Mat4,
}

fn caster_desc(skinned: bool) -> PipelineDesc {
    PipelineDesc {
        name: if skinned { "shadow texture caster (skinned)" } else { "shadow texture caster" },
        vertex_shader: if skinned { "planar_texture_caster_skinned.vert" } else { "planar_texture_caster.vert" },
        fragment_shader: "object_colour.frag",
        vertex_layout: if skinned { super::skin::SKINNED_LAYOUT } else { VertexLayout::POSITION_NORMAL },
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster: RasterState::CULL_NONE,
            depth: DepthState::OFF,
            stencil: None,
            blend: BlendState::OPAQUE,
        },
        push_constant_bytes: OBJECT_PUSH_BYTES,
        subpass: 0,
    }
}

pub fn receive_desc() -> PipelineDesc {
    PipelineDesc {
        name: "shadow texture receive",
        vertex_shader: "planar_texture_receive.vert",
        fragment_shader: "planar_texture_receive.frag",
        vertex_layout: VertexLayout::POSITION_NORMAL,
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster: RasterState { depth_bias: Some(SHADOW_BIAS), ..RasterState::CULL_BACK },
            depth: DepthState { compare: Some(vk::CompareOp::LESS_OR_EQUAL), write: false },
            stencil: None,
            blend: BlendState {
                colour: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::SRC_COLOR)),
                alpha: None,
                write_mask: super::RGB_ONLY,
            },
        },
        push_constant_bytes: std::mem::size_of::<ReceivePush>() as u32,
        subpass: 0,
    }
}

/// Every pipeline of the technique (for `nostencil passes`).
pub fn pipeline_descs() -> Vec<PipelineDesc> {
    let mut descs = vec![caster_desc(false), caster_desc(true)];
    descs.extend(lit_descs());
    descs.push(receive_desc());
    descs
}

/// The light's view-projection, fitted around the casters' bounds: orthographic along a
/// directional light, perspective from a point light. Depth runs 0..1 (it is not used).
pub fn light_view_projection(light: &Light, low: Vec3, high: Vec3) -> Mat4 {
    let centre = (low + high) * 0.5;
    let radius = ((high - low).length() * 0.5).max(1e-3);
    let up_for = |dir: Vec3| if dir.normalize().y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    match *light {
        Light::Directional { direction } => {
            let l = direction.normalize();
            let view = Mat4::look_at_rh(centre - l * (2.0 * radius), centre, up_for(l));
            Mat4::orthographic_rh(-radius, radius, -radius, radius, 0.0, 4.0 * radius) * view
        }
        Light::Point { position } => {
            let to_centre = centre - position;
            let distance = to_centre.length().max(1e-3);
            let half_angle = (radius / distance).min(0.99).asin().min(80f32.to_radians()) * 1.05;
            let near = (distance - radius).max(distance * 0.01);
            let view = Mat4::look_at_rh(position, centre, up_for(to_centre));
            Mat4::perspective_rh(2.0 * half_angle, 1.0, near, distance + 4.0 * radius) * view
        }
    }
}

/// The offscreen target: image, render pass and framebuffer. Cleared (nothing of the last
/// frame is kept), stored (the frame samples it), and left ready for sampling.
struct ShadowTarget {
    // Field order: the framebuffer goes before the render pass and image it refers to.
    framebuffer: Framebuffer,
    render_pass: RenderPass,
    image: Image,
}

impl ShadowTarget {
    fn new(gpu: &Arc<Gpu>) -> Result<Self> {
        let extent = vk::Extent2D { width: SHADOW_TEXTURE_SIZE, height: SHADOW_TEXTURE_SIZE };
        let image = Image::new(
            gpu,
            &ImageDesc {
                name: "shadow texture",
                format: SHADOW_TEXTURE_FORMAT,
                extent,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                aspect: vk::ImageAspectFlags::COLOR,
                mip_levels: 1,
            },
        )?;
        let render_pass =
            colour_render_pass(gpu, SHADOW_TEXTURE_FORMAT, true, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)?;
        let framebuffer = Framebuffer::new(gpu, &render_pass, image.view, extent)?;
        Ok(ShadowTarget { framebuffer, render_pass, image })
    }
}

pub struct ShadowTextureRenderer<'s> {
    scene: &'s Scene,
    shadow_factor: u8,
    renderer: Renderer,
    meshes: SceneMeshes,
    plane: ReceiverPlane,
    scene_pipeline: Pipeline,
    scene_skinned: Pipeline,
    caster: Pipeline,
    caster_skinned: Pipeline,
    receive: Pipeline,
    // Field order: the set goes before the sampler and target it points at.
    texture_set: DescriptorSet,
    _sampler: Sampler,
    target: ShadowTarget,
}

impl<'s> ShadowTextureRenderer<'s> {
    pub fn new(
        gpu: &Arc<Gpu>,
        scene: &'s Scene,
        width: u32,
        height: u32,
        stencil: StencilMode,
        shadow_factor: u8,
    ) -> Result<Self> {
        let plane = receiver_plane(scene)?;
        let renderer = Renderer::new(gpu, width, height, stencil, false)?;
        let meshes = SceneMeshes::upload(gpu, scene)?;
        let target = ShadowTarget::new(gpu)?;
        let sampler = Sampler::new(gpu, vk::Filter::LINEAR, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let texture_set = DescriptorSet::new(
            gpu,
            &[Binding::Texture {
                view: target.image.view,
                sampler: sampler.raw,
                layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                stages: vk::ShaderStageFlags::FRAGMENT,
            }],
        )?;
        let frame_layout = renderer.frame.layout;
        let palette_layout = meshes.template.descriptors.layout;
        let render_pass = renderer.targets.render_pass;
        let [scene_desc, skinned_desc] = lit_descs();
        Ok(ShadowTextureRenderer {
            scene_pipeline: Pipeline::new(gpu, &scene_desc, render_pass, &[frame_layout])?,
            scene_skinned: Pipeline::new(gpu, &skinned_desc, render_pass, &[frame_layout, palette_layout])?,
            caster: Pipeline::new(gpu, &caster_desc(false), target.render_pass.raw, &[])?,
            caster_skinned: Pipeline::new(
                gpu,
                &caster_desc(true),
                target.render_pass.raw,
                &[frame_layout, palette_layout],
            )?,
            receive: Pipeline::new(gpu, &receive_desc(), render_pass, &[frame_layout, texture_set.layout])?,
            scene,
            shadow_factor,
            renderer,
            meshes,
            plane,
            texture_set,
            _sampler: sampler,
            target,
        })
    }

    pub fn renderer_mut(&mut self) -> &mut Renderer {
        &mut self.renderer
    }

    /// Renders the scene this renderer was built for.
    pub fn frame(&mut self) -> Result<PlanarFrame> {
        let scene = self.scene;
        self.frame_with(scene)
    }

    /// Renders `scene`, a moved pose of the one this renderer was built for.
    pub fn frame_with(&mut self, scene: &Scene) -> Result<PlanarFrame> {
        crate::technique::check_same_scene(self.scene, scene, "shadow-texture")?;
        self.meshes.update_palettes(scene)?;
        let uniforms = FrameUniforms::for_scene(scene, self.renderer.aspect());
        let factor = self.shadow_factor as f32 / 255.0;
        let bounds = caster_bounds(scene, &self.plane);
        let light_view_proj = match bounds {
            Some((low, high)) if light_reaches_plane(&scene.light, self.plane.height) => {
                light_view_projection(&scene.light, low, high)
            }
            // Nothing to draw: the texture stays clear and every lookup reads 1.
            _ => Mat4::ZERO,
        };
        let clear = scene.background.extend(1.0).to_array();
        let extent = vk::Extent2D { width: SHADOW_TEXTURE_SIZE, height: SHADOW_TEXTURE_SIZE };
        let white = [vk::ClearValue { color: vk::ClearColorValue { float32: [1.0; 4] } }];
        let ShadowTextureRenderer {
            renderer,
            meshes,
            plane,
            scene_pipeline,
            scene_skinned,
            caster,
            caster_skinned,
            receive,
            texture_set,
            target,
            ..
        } = self;
        let (meshes, plane, set) = (&*meshes, &*plane, texture_set.set);
        let output = renderer.render_with_prepass(
            &uniforms,
            clear,
            |rec| {
                rec.pass("shadow texture", |rec| {
                    rec.begin_offscreen_pass(&target.render_pass, target.framebuffer.raw, extent, &white);
                    // No light above the plane: the texture stays cleared to white (unshadowed).
                    if light_view_proj != Mat4::ZERO {
                        for (index, object) in scene.objects.iter().enumerate().filter(|(i, _)| !plane.receivers[*i]) {
                            let push = ObjectPush {
                                model: light_view_proj * object.transform,
                                colour: Vec4::new(factor, factor, factor, 1.0),
                            };
                            meshes.draw(rec, scene, index, caster, caster_skinned, &push);
                        }
                    }
                    rec.end_render_pass();
                    Ok(())
                })
            },
            |rec| {
                rec.pass("scene", |rec| {
                    for (index, object) in scene.objects.iter().enumerate() {
                        let push = ObjectPush { model: object.transform, colour: object.colour.extend(1.0) };
                        meshes.draw(rec, scene, index, scene_pipeline, scene_skinned, &push);
                    }
                    Ok(())
                })?;
                rec.pass("shadow texture receive", |rec| {
                    super::bind_set1(rec, receive, set);
                    for object in scene.objects.iter().zip(&plane.receivers).filter(|(_, r)| **r).map(|(o, _)| o) {
                        rec.push(receive, &ReceivePush { model: object.transform, light_view_proj });
                        rec.draw_mesh(&meshes.meshes.meshes[object.mesh]);
                    }
                    Ok(())
                })
            },
        )?;
        Ok(PlanarFrame { output, stats: stats(&self.plane, &self.meshes, self.shadow_factor) })
    }
}

/// Renders `scene` with a render-texture shadow.
pub fn render(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    width: u32,
    height: u32,
    stencil: StencilMode,
    shadow_factor: u8,
) -> Result<PlanarFrame> {
    ShadowTextureRenderer::new(gpu, scene, width, height, stencil, shadow_factor)?.frame()
}
