//! Render-texture shadows (seed 001): the casters drawn in one flat shade into a small texture
//! from the light (orthographic along a directional light, perspective from a point light),
//! then looked up by the receivers through the same light projection. Memory bounds the
//! texture's size, so the shadow's edges show its texels; a caster leaving the light's frustum
//! would be cut, so the frustum is fitted to the casters' posed bounds every frame.
//!
//! Frame:
//! 1. prepass "shadow texture" (its own render pass, NxN RGBA8, N = `--render-texture-size`,
//!    default 128, cleared to 1): every caster (GPU-skinned; simplified with `--shadow-lod`)
//!    written with colour F/255, opaque, no depth: overlaps write the same value, so nothing can
//!    darken twice. Stored and left SHADER_READ_ONLY_OPTIMAL.
//! 2. scene: lit objects (GPU-skinned).
//! 3. "shadow texture receive": the receivers drawn again, depth LESS_OR_EQUAL with the planar
//!    bias, each pixel's factor read from the texture (1 outside it), colour blend
//!    `ADD, ZERO, SRC_COLOR`; or, as the seed lays it (`--render-texture-on quad`), "shadow
//!    texture quad": one quad on the plane around the casters' shadow ([`super::texture_quad`])
//!    with the same lookup, not clipped to the receivers.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3, Vec4};

use super::lod::CasterLods;
use super::receiver::{caster_bounds, light_reaches_plane, receiver_plane, ReceiverPlane};
use super::scene_meshes::{lit_scene_pass, scene_sets, SceneMeshes};
use super::shared::{PlanarStats, ShadowTexture, DEFAULT_SHADOW_LOD, SHADOW_BIAS};
use super::texture_quad::{quad_model, shadow_quad, unit_square};
use crate::error::{Error, Result};
use crate::frame::offscreen::{colour_render_pass, Framebuffer, RenderPass};
use crate::frame::StencilMode;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::{Image, ImageDesc};
use crate::gpu::texture::Sampler;
use crate::gpu::Gpu;
use crate::pipeline::recipes::MODULATE_BY_SRC_COLOUR;
use crate::pipeline::{BlendState, DepthState, FixedFunction, PipelineDesc, RasterState, VertexLayout};
use crate::render::passes::Passes;
use crate::render::per_slot::slot_copy;
use crate::render::plan::{DrawKind, Label, MaterialVariant, PassKinds, PassPlan, PlannedPass, SetRole};
use crate::render::Pipeline;
use crate::render::{FrameOutput, FrameRecorder, GpuMesh, GpuScene, ObjectPush, Renderer, OBJECT_PUSH_BYTES};
use crate::scene::{Light, Scene};
use crate::shaders;
use crate::technique::frame_renderer::BuildContext;
use crate::technique::interface::{FrameStats, Variant};
use crate::technique::interface::{RenderOptions, TechniqueInfo};
use crate::technique::light_loop::{PlannedLight, ShadowedLights};
use crate::technique::options::{PlanarOptions, TextureShadowOn};
use crate::technique::shadow_tone::ShadowTone;
use crate::technique::unit::{Prepared, TechniqueUnit};

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
        vertex_shader: if skinned {
            shaders::PLANAR_TEXTURE_CASTER_SKINNED_VERT
        } else {
            shaders::PLANAR_TEXTURE_CASTER_VERT
        },
        fragment_shader: shaders::OBJECT_COLOUR_FRAG,
        vertex_layout: if skinned { VertexLayout::SKINNED_SCENE } else { VertexLayout::SCENE },
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster: RasterState::CULL_NONE,
            depth: DepthState::OFF,
            stencil: None,
            blend: BlendState::OPAQUE,
        },
        push_constant_bytes: OBJECT_PUSH_BYTES,
    }
}

pub fn receive_desc() -> PipelineDesc {
    PipelineDesc {
        name: "shadow texture receive",
        vertex_shader: shaders::PLANAR_TEXTURE_RECEIVE_VERT,
        fragment_shader: shaders::PLANAR_TEXTURE_RECEIVE_FRAG,
        vertex_layout: VertexLayout::SCENE,
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster: RasterState { depth_bias: Some(SHADOW_BIAS), ..RasterState::CULL_BACK },
            depth: DepthState { compare: Some(vk::CompareOp::LESS_OR_EQUAL), write: false },
            stencil: None,
            blend: MODULATE_BY_SRC_COLOUR,
        },
        push_constant_bytes: std::mem::size_of::<ReceivePush>() as u32,
    }
}

/// The seed's quad: the receive pipeline on one flat quad seen from either side.
pub fn quad_desc() -> PipelineDesc {
    let receive = receive_desc();
    PipelineDesc {
        name: "shadow texture quad",
        fixed: FixedFunction {
            raster: RasterState { depth_bias: Some(SHADOW_BIAS), ..RasterState::CULL_NONE },
            ..receive.fixed
        },
        ..receive
    }
}

/// The kinds of the render-texture shadow's plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TextureKinds;

impl PassKinds for TextureKinds {
    type Draw = TextureDraw;
    type Set = TextureSet;
    type Target = TextureTarget;
}

/// What the render-texture shadow draws itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TextureDraw {
    /// The casters seen from the light, or (`lod`) their simplified meshes.
    CastersFromTheLight { lod: bool },
    /// Every object, lit.
    Scene,
    /// The receivers again, darkened by their lookup.
    Receivers,
    /// The seed's quad on the plane around the casters' shadow.
    Quad,
}

impl DrawKind for TextureDraw {
    fn describe(self) -> &'static str {
        match self {
            TextureDraw::CastersFromTheLight { lod: false } => "casters seen from the light",
            TextureDraw::CastersFromTheLight { lod: true } => "simplified casters (meshoptimizer) seen from the light",
            TextureDraw::Scene => "objects",
            TextureDraw::Receivers => "receivers",
            TextureDraw::Quad => "one quad on the plane around the casters' shadow",
        }
    }
}

/// The render-texture shadow's descriptor sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TextureSet {
    /// The shadow texture, at set 1 of the receive pass.
    ShadowTexture,
}

impl Label for TextureSet {
    fn label(self) -> &'static str {
        match self {
            TextureSet::ShadowTexture => "shadow texture",
        }
    }
}

/// The offscreen target the casters are drawn into.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TextureTarget {
    ShadowTexture,
}

impl Label for TextureTarget {
    fn label(self) -> &'static str {
        match self {
            TextureTarget::ShadowTexture => "shadow texture",
        }
    }
}

/// The frame's passes: the casters into the shadow texture, the lit scene, then the receivers
/// again (or the seed's quad), darkened by their lookup.
pub fn plan(options: &PlanarOptions) -> PassPlan<TextureKinds> {
    let casters = PlannedPass::offscreen(
        "shadow texture",
        caster_desc(false),
        TextureDraw::CastersFromTheLight { lod: options.shadow_lod.is_some() },
        "light view-projection x object transform, colour F/255",
        TextureTarget::ShadowTexture,
    )
    .or_pipeline(caster_desc(true))
    .or_variant(
        MaterialVariant::Masked,
        caster_desc(false).name,
        PipelineDesc {
            name: "shadow texture caster (alpha mask)",
            vertex_shader: shaders::PLANAR_TEXTURE_CASTER_MASKED_VERT,
            fragment_shader: shaders::OBJECT_COLOUR_MASKED_FRAG,
            ..caster_desc(false)
        },
    )
    .or_variant(
        MaterialVariant::Masked,
        caster_desc(true).name,
        PipelineDesc {
            name: "shadow texture caster (skinned, alpha mask)",
            vertex_shader: shaders::PLANAR_TEXTURE_CASTER_MASKED_SKINNED_VERT,
            fragment_shader: shaders::OBJECT_COLOUR_MASKED_FRAG,
            ..caster_desc(true)
        },
    )
    .with_sets(&scene_sets());
    let receive = match options.texture_on {
        TextureShadowOn::Receivers => PlannedPass::own(
            "shadow texture receive",
            receive_desc(),
            TextureDraw::Receivers,
            "receiver transform and the light's view-projection",
        ),
        TextureShadowOn::Quad => PlannedPass::own(
            "shadow texture quad",
            quad_desc(),
            TextureDraw::Quad,
            "the quad's placement on the plane and the light's view-projection",
        ),
    }
    .with_sets(&[SetRole::Frame, SetRole::Own(TextureSet::ShadowTexture)]);
    PassPlan { passes: vec![casters, lit_scene_pass(TextureDraw::Scene), receive] }
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

/// The offscreen target: image, render pass and framebuffer, and the set the frame samples it
/// through. Cleared (nothing of the last frame is kept), stored (the frame samples it), and left
/// ready for sampling. One per frame slot: a frame in flight samples its own.
struct ShadowTarget {
    // Field order: the set goes before the image it points at, the framebuffer before the render
    // pass and image it refers to.
    texture_set: DescriptorSet,
    framebuffer: Framebuffer,
    render_pass: RenderPass,
    _image: Image,
}

impl ShadowTarget {
    fn new(gpu: &Arc<Gpu>, size: u32, sampler: &Sampler) -> Result<Self> {
        let extent = vk::Extent2D { width: size, height: size };
        let image = Image::new(
            gpu,
            &ImageDesc {
                name: "shadow texture",
                format: SHADOW_TEXTURE_FORMAT,
                extent,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                aspect: vk::ImageAspectFlags::COLOR,
                mip_levels: 1,
                samples: 1,
            },
        )?;
        let render_pass =
            colour_render_pass(gpu, SHADOW_TEXTURE_FORMAT, true, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)?;
        let framebuffer = Framebuffer::new(gpu, &render_pass, image.view, extent)?;
        let texture_set = DescriptorSet::new(
            gpu,
            &[Binding::Texture {
                view: image.view,
                sampler: sampler.raw,
                layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                stages: vk::ShaderStageFlags::FRAGMENT,
            }],
        )?;
        Ok(ShadowTarget { texture_set, framebuffer, render_pass, _image: image })
    }
}

impl TechniqueInfo for ShadowTexture {
    fn name(&self) -> &'static str {
        "shadow-texture"
    }

    fn shadowed_lights(&self, _options: &RenderOptions, _lights: &[PlannedLight]) -> ShadowedLights {
        ShadowedLights::Primary
    }

    fn about(&self) -> &'static str {
        "casters drawn from the light into a small texture that the ground looks up (seed 001)"
    }

    /// The texture on the receivers and on the seed's quad, each also from simplified casters.
    fn plan_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        let lod = Some(options.planar.shadow_lod.unwrap_or(DEFAULT_SHADOW_LOD));
        [
            (TextureShadowOn::Receivers, None),
            (TextureShadowOn::Quad, None),
            (TextureShadowOn::Receivers, lod),
            (TextureShadowOn::Quad, lod),
        ]
        .into_iter()
        .map(|(texture_on, shadow_lod)| Variant {
            label: format!(
                "{} (on {}{})",
                self.name(),
                texture_on.name(),
                if shadow_lod.is_some() { ", shadow LOD" } else { "" }
            ),
            options: RenderOptions {
                stencil: StencilMode::Emulated,
                planar: PlanarOptions { texture_on, shadow_lod, ..options.planar },
                ..options.clone()
            },
        })
        .collect()
    }

    fn bench_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        super::shared::bench_variants(options)
    }
}

impl TechniqueUnit for ShadowTexture {
    type Kinds = TextureKinds;
    type Setup = ();
    type Passes = ShadowTexturePasses;

    fn plan(&self, options: &RenderOptions, _lights: &[PlannedLight]) -> Result<PassPlan<TextureKinds>> {
        Ok(plan(&options.planar))
    }

    fn setup(&self, _gpu: &Gpu, _scene: &Scene, options: &RenderOptions) -> Result<Prepared<()>> {
        Ok(Prepared::as_given(options))
    }

    fn make(&self, ctx: BuildContext<'_>, scene: &Scene, _setup: ()) -> Result<ShadowTexturePasses> {
        ShadowTexturePasses::new(&ctx, scene)
    }
}

/// The shadow-texture renderer's own part: the scene's meshes, the texture and its lookup, and
/// this frame's light view-projection.
pub struct ShadowTexturePasses {
    tone: ShadowTone,
    texture_size: u32,
    plane: ReceiverPlane,
    meshes: SceneMeshes,
    /// The casters' simplified meshes, with `--shadow-lod`.
    lods: Option<CasterLods>,
    /// The seed's quad (`--render-texture-on quad`), and this frame's placement of it.
    quad: Option<GpuMesh>,
    quad_model: Option<Mat4>,
    /// Fitted around the casters each frame; zero when there is nothing to draw (the texture
    /// stays clear and every lookup reads 1).
    light_view_proj: Mat4,
    // Field order: the targets (their sets) go before the sampler the sets point at.
    /// Per frame slot, the texture its frame renders and samples.
    targets: Vec<ShadowTarget>,
    sampler: Sampler,
    /// The slot of the frame being recorded (`prepare`'s), whose target the passes use.
    slot: usize,
}

impl ShadowTexturePasses {
    fn new(ctx: &BuildContext, scene: &Scene) -> Result<Self> {
        let gpu = ctx.gpu;
        let plane = receiver_plane(scene, ctx.options.planar.plane.as_ref())?;
        plane.plane.check_light(&scene.light())?;
        let meshes = SceneMeshes::upload(gpu, scene, ctx.options.skinning)?;
        let options = &ctx.options.planar;
        let lods = match options.shadow_lod {
            Some(ratio) => Some(CasterLods::build(gpu, scene, &plane.receivers, ratio)?),
            None => None,
        };
        let quad = match options.texture_on {
            TextureShadowOn::Quad => Some(unit_square(gpu)?),
            TextureShadowOn::Receivers => None,
        };
        let sampler = Sampler::new(gpu, vk::Filter::LINEAR, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let target = ShadowTarget::new(gpu, options.texture_size, &sampler)?;
        Ok(ShadowTexturePasses {
            tone: ctx.options.shadow_tone,
            texture_size: options.texture_size,
            plane,
            meshes,
            lods,
            quad,
            quad_model: None,
            light_view_proj: Mat4::ZERO,
            targets: vec![target],
            sampler,
            slot: 0,
        })
    }

    /// The prepass: its own render pass, cleared to white (unshadowed), then every caster in
    /// the flat shade F/255 (`[static, skinned]` pipelines).
    fn draw_casters(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        pass: &PlannedPass<TextureKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        let &[caster, skinned, ..] = pipelines else {
            return Err(Error::Internal(format!("the shadow texture pass has {} pipelines", pipelines.len())));
        };
        let extent = vk::Extent2D { width: self.texture_size, height: self.texture_size };
        let white = [vk::ClearValue { color: vk::ClearColorValue { float32: [1.0; 4] } }];
        let target = self.target();
        rec.begin_offscreen_pass(&target.render_pass, target.framebuffer.raw, extent, &white);
        // No light above the plane: the texture stays cleared to white (unshadowed).
        if self.light_view_proj != Mat4::ZERO {
            let factor = self.tone.darkest_factor();
            for (index, object) in scene.objects.iter().enumerate().filter(|(i, _)| !self.plane.receivers[*i]) {
                let push = ObjectPush {
                    model: self.light_view_proj * object.transform,
                    colour: Vec4::new(factor, factor, factor, 1.0),
                };
                let casters = SceneMeshes::caster_pipelines(scene, index, pass, pipelines, [caster, skinned]);
                self.meshes.draw_caster(rec, scene, index, casters, &push, self.lods.as_ref());
            }
        }
        rec.end_render_pass();
        Ok(())
    }

    /// The receivers drawn again, each pixel darkened by its lookup.
    fn draw_receivers(&self, rec: &mut FrameRecorder, scene: &Scene, pipelines: &[&Pipeline]) -> Result<()> {
        let &[receive] = pipelines else {
            return Err(Error::Internal(format!("the shadow texture receive pass has {} pipelines", pipelines.len())));
        };
        let light_view_proj = self.light_view_proj;
        for object in scene.objects.iter().zip(&self.plane.receivers).filter(|(_, r)| **r).map(|(o, _)| o) {
            rec.push(receive, &ReceivePush { model: object.transform, light_view_proj });
            rec.draw_mesh(&self.meshes.meshes.meshes[object.mesh]);
        }
        Ok(())
    }
}

impl ShadowTexturePasses {
    /// The target of the frame being recorded.
    fn target(&self) -> &ShadowTarget {
        self.targets.get(self.slot).unwrap_or(&self.targets[0])
    }

    /// The seed's quad around the casters' shadow, looking the texture up like a receiver.
    fn draw_quad(&self, rec: &mut FrameRecorder, pipelines: &[&Pipeline]) -> Result<()> {
        let &[quad_pipeline] = pipelines else {
            return Err(Error::Internal(format!("the shadow texture quad pass has {} pipelines", pipelines.len())));
        };
        if let (Some(quad), Some(model)) = (&self.quad, self.quad_model) {
            if self.light_view_proj != Mat4::ZERO {
                rec.push(quad_pipeline, &ReceivePush { model, light_view_proj: self.light_view_proj });
                rec.draw_mesh(quad);
            }
        }
        Ok(())
    }
}

impl Passes<TextureKinds> for ShadowTexturePasses {
    fn set(&self, set: TextureSet) -> Option<&DescriptorSet> {
        match set {
            TextureSet::ShadowTexture => Some(&self.target().texture_set),
        }
    }

    fn meshes(&self) -> Option<&GpuScene> {
        Some(&self.meshes.meshes)
    }

    fn draw(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draw: TextureDraw,
        pass: &PlannedPass<TextureKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        match draw {
            TextureDraw::CastersFromTheLight { .. } => self.draw_casters(rec, scene, pass, pipelines),
            TextureDraw::Scene => self.meshes.draw_scene(rec, scene, &self.plane, pass, pipelines, 1.0),
            TextureDraw::Receivers => self.draw_receivers(rec, scene, pipelines),
            TextureDraw::Quad => self.draw_quad(rec, pipelines),
        }
    }

    fn offscreen_pass(&self, target: TextureTarget) -> Option<(vk::RenderPass, usize)> {
        match target {
            // Every slot's render pass is made alike: the pipelines built for slot 0's fit all.
            TextureTarget::ShadowTexture => Some((self.targets[0].render_pass.raw, 1)),
        }
    }

    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()> {
        self.plane.plane.check_light(&scene.light())?;
        self.slot = renderer.slot();
        let (size, sampler) = (self.texture_size, &self.sampler);
        slot_copy(&mut self.targets, self.slot, || ShadowTarget::new(&renderer.gpu, size, sampler))?;
        self.meshes.follow_pose(&renderer.gpu, scene, self.slot)?;
        self.quad_model = match self.quad {
            Some(_) => shadow_quad(scene, &self.plane).map(|corners| quad_model(&corners, self.plane.plane.normal)),
            None => None,
        };
        self.light_view_proj = match caster_bounds(scene, &self.plane) {
            Some((low, high)) if light_reaches_plane(&scene.light(), &self.plane.plane) => {
                light_view_projection(&scene.light(), low, high)
            }
            _ => Mat4::ZERO,
        };
        Ok(())
    }

    /// Palettes and the shadow texture are the slot's own.
    fn writes_per_slot(&self) -> bool {
        true
    }

    /// Its plan names its skinned pipelines itself (`lit_scene_pass`, `caster_desc`).
    fn skinned_twins(&self) -> bool {
        false
    }

    fn stats(&mut self, _output: &FrameOutput, _scene: &Scene) -> Box<dyn FrameStats> {
        Box::new(PlanarStats::of(&self.plane, &self.meshes, self.tone).with_lods(self.lods.as_ref()))
    }
}
