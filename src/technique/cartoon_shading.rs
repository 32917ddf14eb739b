//! The scene pass the cartoon techniques share (seed 002's shading): Lambert, or N.L through a
//! toon ramp, optionally darkened by a rim ramp looked up at N.V. Its push constants are also
//! those of the extruded copies and the ink quads; the ramps are bound at set 1.

use image::{Rgba, RgbaImage};
use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec4};

use crate::error::Result;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::texture::{Sampler, Texture};
use crate::gpu::Gpu;
use crate::pipeline::{FixedFunction, PipelineDesc, VertexLayout};
use crate::render::object_push::draw_order;
use crate::render::plan::{Label, MaterialVariant, PassKinds, PlannedPass, SetRole};
use crate::render::Pipeline;
use crate::render::{FrameRecorder, GpuScene, Skinning};
use crate::scene::Scene;
use crate::shaders;
use crate::technique::material_variants::with_surface_variants;

/// Mirrors `CartoonPush` in `shaders/cartoon_push.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct CartoonPush {
    pub model: Mat4,
    pub colour: Vec4,
    pub params: Vec4,
    pub viewport: Vec4,
}

pub const CARTOON_PUSH_BYTES: u32 = std::mem::size_of::<CartoonPush>() as u32;

/// A technique's set kinds that include the toon and rim ramps, bound at set 2 of the scene
/// pass by [`shade_pass`] (the frame's uniforms are set 0, the material set 1).
pub trait WithRamps: Label {
    const RAMPS: Self;
}

/// A pipeline of the cartoon shaders (they all push a `CartoonPush`).
pub fn cartoon_desc(
    name: &'static str,
    vertex_shader: shaders::Shader,
    fragment_shader: shaders::Shader,
    vertex_layout: VertexLayout,
    fixed: FixedFunction,
) -> PipelineDesc {
    PipelineDesc { name, vertex_shader, fragment_shader, vertex_layout, fixed, push_constant_bytes: CARTOON_PUSH_BYTES }
}

/// The scene: Lambert or toon, optionally with the N.V rim; writes the alpha it is given.
pub fn shade_desc() -> PipelineDesc {
    cartoon_desc(
        "scene",
        shaders::CARTOON_SHADE_VERT,
        shaders::CARTOON_SHADE_FRAG,
        VertexLayout::SCENE,
        FixedFunction::OPAQUE,
    )
}

/// A scene pass: the objects `draw` names, shaded by [`shade_desc`] or a variant of it, with
/// the frame's uniforms, their materials and the ramps.
pub fn shade_pass<K: PassKinds>(
    name: &'static str,
    pipeline: PipelineDesc,
    draw: K::Draw,
    push: &'static str,
) -> PlannedPass<K>
where
    K::Set: WithRamps,
{
    let pass = PlannedPass::own(name, pipeline.clone(), draw, push);
    with_surface_variants(pass, &pipeline).with_sets(&[SetRole::Frame, SetRole::Material, SetRole::Own(K::Set::RAMPS)])
}

/// How the scene pass shades.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Shading {
    /// N.L through the toon ramp, instead of Lambert.
    pub toon: bool,
    /// Times the rim ramp at N.V (`--silhouette shader`).
    pub rim: bool,
    /// Faces flat in the scene's background colour, unlit (`--ink-only`).
    pub ink_only: bool,
}

impl Shading {
    /// `CartoonPush::params` of `cartoon_shade`.
    fn params(self) -> Vec4 {
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        Vec4::new(flag(self.toon), flag(self.rim), flag(self.ink_only), 0.0)
    }
}

/// World size of one pixel at unit distance from the eye, for a target `height` pixels high.
pub fn pixel_at_unit_distance(scene: &Scene, height: u32) -> f32 {
    2.0 * (0.5 * scene.camera.fov_y_radians).tan() / height as f32
}

/// `CartoonPush::viewport`: the target's size in pixels and the world size of one pixel at unit
/// distance (what turns a width in pixels into an extrusion).
pub fn viewport(scene: &Scene, extent: vk::Extent2D) -> Vec4 {
    Vec4::new(extent.width as f32, extent.height as f32, pixel_at_unit_distance(scene, extent.height), 0.0)
}

/// The scene as the cartoon techniques draw it: its meshes, the ramps, and how it is shaded.
pub struct CartoonScene {
    pub meshes: GpuScene,
    pub ramps: Ramps,
    pub shading: Shading,
}

impl CartoonScene {
    /// `skinning`: where skinned objects are posed (the scene pass has skinned twins; ink
    /// edges and extruded copies are found on the CPU from the pose whatever is asked).
    pub fn new(gpu: &Arc<Gpu>, scene: &Scene, shading: Shading, skinning: Skinning) -> Result<Self> {
        Ok(CartoonScene { meshes: GpuScene::upload_for(gpu, scene, skinning)?, ramps: Ramps::new(gpu)?, shading })
    }

    /// The ramps' set.
    pub fn ramps(&self) -> &DescriptorSet {
        &self.ramps.set
    }

    /// Draws the objects `which` picks (in `draw_order`) with the pass's pipeline their
    /// material needs (`pipelines`: the pass's, the main one bound), each with its transform,
    /// material and the alpha `alpha`.
    #[allow(clippy::too_many_arguments)]
    pub fn draw<K: PassKinds>(
        &self,
        rec: &mut FrameRecorder,
        pass: &PlannedPass<K>,
        pipelines: &[&Pipeline],
        scene: &Scene,
        which: impl Fn(usize) -> bool,
        alpha: f32,
        viewport: Vec4,
    ) -> Result<()> {
        let Some(&main) = pipelines.first() else { return Ok(()) };
        let mut bound = main;
        for index in draw_order(scene).filter(|i| which(*i)) {
            bound = self.draw_object(rec, pass, pipelines, bound, scene, index, alpha, viewport)?;
        }
        Ok(())
    }

    /// Draws object `index` as [`CartoonScene::draw`] does, `bound` being the pipeline bound
    /// now (rebound only when its material needs another, or its skinned twin); returns the one
    /// bound after.
    #[allow(clippy::too_many_arguments)]
    pub fn draw_object<'p, K: PassKinds>(
        &self,
        rec: &mut FrameRecorder,
        pass: &PlannedPass<K>,
        pipelines: &[&'p Pipeline],
        bound: &'p Pipeline,
        scene: &Scene,
        index: usize,
        alpha: f32,
        viewport: Vec4,
    ) -> Result<&'p Pipeline> {
        let Some(&main) = pipelines.first() else { return Ok(bound) };
        let object = &scene.objects[index];
        let variant = MaterialVariant::for_surface(scene.material_of(object));
        let (mesh, pipeline) = self.meshes.object_draw(scene, index, pass.variant(pipelines, main, variant))?;
        if !std::ptr::eq(pipeline, bound) {
            rec.bind(pipeline);
        }
        let colour =
            if self.shading.ink_only { background_fill(scene) } else { scene.base_colour(object) }.extend(alpha);
        rec.bind_material(pipeline, self.meshes.materials.set(object.material));
        rec.push(pipeline, &CartoonPush { model: object.transform, colour, params: self.shading.params(), viewport });
        rec.draw_mesh(mesh);
        Ok(pipeline)
    }
}

/// `--ink-only`'s face colour: the background, snapped to the middle of its 8-bit sRGB code. The
/// sky is the clear colour, converted to sRGB by the clear; the faces are the same colour written
/// by a shader, converted by the blend unit's own path, and Vulkan lets the two round a value
/// near a code's edge differently (lavapipe turns 0.78 into 229 in a clear, 228 from a shader).
/// From a code's middle both land on it.
fn background_fill(scene: &Scene) -> glam::Vec3 {
    let snap = |linear: f32| crate::frame::srgb::decode(crate::frame::srgb::encode(linear));
    glam::Vec3::new(snap(scene.background.x), snap(scene.background.y), snap(scene.background.z))
}

// ---------------------------------------------------------------------------------------------
// The ramps: Nx1 RGBA8, nearest filtering.

/// N.L -> light: three flat bands (shadow, mid, lit), as cel painters use.
pub fn toon_ramp() -> RgbaImage {
    RgbaImage::from_fn(16, 1, |i, _| {
        let level: u8 = match i {
            0..=4 => 110,
            5..=10 => 190,
            _ => 255,
        };
        Rgba([level, level, level, 255])
    })
}

/// N.V -> ink: the first texels (grazing angles) black, the rest white (seed 002: "1x32, the
/// first few texels near u = 0 black"). N.V < 0.44 is dark: on a sphere that is the outer 10%
/// of its radius on screen (N.V falls fast near the contour, so fewer texels draw a hairline).
pub fn rim_ramp() -> RgbaImage {
    RgbaImage::from_fn(32, 1, |i, _| {
        let level = if i < 14 { 0 } else { 255 };
        Rgba([level, level, level, 255])
    })
}

/// Both ramps on the GPU, in one descriptor set (`WithRamps::RAMPS`, set 2 of the scene pass).
pub struct Ramps {
    pub set: DescriptorSet,
    _ramp: Texture,
    _rim: Texture,
}

impl Ramps {
    pub fn new(gpu: &Arc<Gpu>) -> Result<Self> {
        let nearest = || Sampler::new(gpu, vk::Filter::NEAREST, vk::SamplerAddressMode::CLAMP_TO_EDGE);
        let format = vk::Format::R8G8B8A8_UNORM;
        let ramp = Texture::from_rgba8(gpu, "toon ramp", &toon_ramp(), format, false, nearest()?)?;
        let rim = Texture::from_rgba8(gpu, "rim ramp", &rim_ramp(), format, false, nearest()?)?;
        let binding = |t: &Texture| Binding::Texture {
            view: t.image.view,
            sampler: t.sampler.raw,
            layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            stages: vk::ShaderStageFlags::FRAGMENT,
        };
        let set = DescriptorSet::new(gpu, &[binding(&ramp), binding(&rim)])?;
        Ok(Ramps { set, _ramp: ramp, _rim: rim })
    }
}
