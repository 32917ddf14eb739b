//! Blob shadows (seed 001, the mobile classic): a round, soft-edged texture on a quad lying on
//! the ground under each foot of a skinned character (the seed's two foot-sized circles), or
//! under the root (the centre of the posed bounds) of anything else, darker the closer it is to
//! the ground. Cheap and shape-blind.
//!
//! Frame, one render pass: scene (lit, GPU-skinned), then one draw of every blob quad, depth
//! LESS_OR_EQUAL with the planar bias, colour blend `ADD, ZERO, SRC_COLOR` with the fragment
//! outputting `1 - strength x coverage`. Blobs are soft and meant to overlap where casters stand
//! close: they multiply (no stencil would be wanted there either). No stencil path differs: with
//! `--stencil reference` the same draws run on a depth+stencil target.

use ash::vk;
use glam::{Vec2, Vec3};
use image::{Rgba, RgbaImage};

use super::receiver::{light_reaches_plane, receiver_plane, ReceiverPlane};
use super::scene_meshes::{lit_scene_pass, SceneMeshes};
use super::shared::{BlobShadows, PlanarStats, SHADOW_BIAS};
use crate::error::{Error, Result};
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::ReusedBuffer;
use crate::gpu::texture::{Sampler, Texture};
use crate::gpu::Gpu;
use crate::pipeline::recipes::MODULATE_BY_SRC_COLOUR;
use crate::pipeline::{DepthState, FixedFunction, PipelineDesc, RasterState, VertexAttribute, VertexLayout};
use crate::render::passes::Passes;
use crate::render::per_slot::slot_copy;
use crate::render::plan::{DrawKind, Label, NoOwn, PassKinds, PassPlan, PlannedPass, SetRole};
use crate::render::Pipeline;
use crate::render::{FrameOutput, FrameRecorder, GpuScene, Renderer};
use crate::scene::{bounds_of, Scene};
use crate::shaders;
use crate::technique::frame_renderer::BuildContext;
use crate::technique::interface::{FrameStats, Variant};
use crate::technique::interface::{RenderOptions, TechniqueInfo};
use crate::technique::light_loop::{PlannedLight, ShadowedLights};
use crate::technique::shadow_tone::ShadowTone;
use crate::technique::unit::{Prepared, TechniqueUnit};

/// position (vec3), uv (vec2), strength (float).
pub const BLOB_LAYOUT: VertexLayout =
    VertexLayout { attributes: &[VertexAttribute::Vec3, VertexAttribute::Vec2, VertexAttribute::F32] };

#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct BlobVertex {
    position: [f32; 3],
    uv: [f32; 2],
    strength: f32,
}

/// Side of the generated blob texture.
pub const BLOB_TEXTURE_SIZE: u32 = 64;

/// A radial falloff: coverage 1 inside 40 % of the radius, smoothly 0 at the rim (and beyond).
pub fn blob_image(size: u32) -> RgbaImage {
    RgbaImage::from_fn(size, size, |x, y| {
        let p = (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / size as f32) * 2.0 - Vec2::ONE;
        let t = ((1.0 - p.length()) / 0.6).clamp(0.0, 1.0);
        let coverage = (t * t * (3.0 - 2.0 * t) * 255.0).round() as u8;
        Rgba([coverage; 4])
    })
}

pub fn blob_desc() -> PipelineDesc {
    PipelineDesc {
        name: "blob shadow",
        vertex_shader: shaders::PLANAR_BLOB_VERT,
        fragment_shader: shaders::PLANAR_BLOB_FRAG,
        vertex_layout: BLOB_LAYOUT,
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster: RasterState { depth_bias: Some(SHADOW_BIAS), ..RasterState::CULL_NONE },
            depth: DepthState { compare: Some(vk::CompareOp::LESS_OR_EQUAL), write: false },
            stencil: None,
            blend: MODULATE_BY_SRC_COLOUR,
        },
        push_constant_bytes: 0,
    }
}

/// The kinds of the blob plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BlobKinds;

impl PassKinds for BlobKinds {
    type Draw = BlobDraw;
    type Set = BlobSet;
    type Target = NoOwn;
}

/// What the blob renderer draws itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BlobDraw {
    /// Every object, lit.
    Scene,
    /// One quad per blob.
    Quads,
}

impl DrawKind for BlobDraw {
    fn describe(self) -> &'static str {
        match self {
            BlobDraw::Scene => "objects",
            BlobDraw::Quads => "one quad per blob",
        }
    }
}

/// The blob plan's descriptor sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BlobSet {
    /// The blob texture, at set 1 of the blob pass.
    BlobTexture,
}

impl Label for BlobSet {
    fn label(self) -> &'static str {
        match self {
            BlobSet::BlobTexture => "blob texture",
        }
    }
}

/// The frame's passes: the lit scene, then every blob quad (one draw, none without blobs).
pub fn plan() -> PassPlan<BlobKinds> {
    let blobs = PlannedPass::own("blob shadow", blob_desc(), BlobDraw::Quads, "-")
        .with_sets(&[SetRole::Frame, SetRole::Own(BlobSet::BlobTexture)]);
    PassPlan { passes: vec![lit_scene_pass(BlobDraw::Scene), blobs] }
}

/// One blob: where it lies on the plane, how wide it is and how dark its centre is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Blob {
    pub centre: Vec3,
    pub radius: f32,
    pub strength: f32,
}

/// The blobs of this frame. A skinned caster gets one under each foot: the vertices are grouped
/// by the joint that weighs most on them, and every group that reaches down to the ground (within
/// a tenth of the caster's height) gets a blob under its lowest slice. Other casters (and a
/// skinned one with no such group) get one under the centre of their posed bounds, as wide as
/// the bounds plus a fifth. Blobs fade out as what they stand for rises one caster height.
pub fn blobs(scene: &Scene, plane: &ReceiverPlane, darkness: f32) -> Vec<Blob> {
    let mut blobs = Vec::new();
    for (index, object) in scene.objects.iter().enumerate().filter(|(i, _)| !plane.receivers[*i]) {
        // Posed once: the bounds and the feet both come from it.
        let world = scene.posed_world_positions(index);
        let Some((low, high)) = bounds_of(world.iter().copied()) else { continue };
        let size = high - low;
        let fade = |bottom: f32| darkness * (1.0 - (bottom - plane.height).max(0.0) / size.y.max(1e-3)).clamp(0.0, 1.0);
        let mut feet = Vec::new();
        if let Some(skin) = &object.skin {
            let dominant = |v: usize| {
                let (j, w) = (skin.joints.get(v)?, skin.weights.get(v)?);
                (0..4).max_by(|&a, &b| w[a].total_cmp(&w[b])).map(|k| j[k])
            };
            let mut groups: Vec<(u16, Vec<Vec3>)> = Vec::new();
            for (v, p) in world.iter().enumerate() {
                let Some(joint) = dominant(v) else { continue };
                match groups.iter_mut().find(|(j, _)| *j == joint) {
                    Some((_, points)) => points.push(*p),
                    None => groups.push((joint, vec![*p])),
                }
            }
            for (_, points) in &groups {
                let bottom = points.iter().map(|p| p.y).fold(f32::MAX, f32::min);
                if bottom - plane.height > 0.1 * size.y {
                    continue;
                }
                let slice: Vec<Vec3> = points.iter().copied().filter(|p| p.y <= bottom + 0.05 * size.y).collect();
                let (lo, hi) = slice
                    .iter()
                    .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(l, h), p| (l.min(*p), h.max(*p)));
                let extent = (hi - lo).x.max((hi - lo).z);
                feet.push(Blob {
                    centre: Vec3::new((lo.x + hi.x) * 0.5, plane.height, (lo.z + hi.z) * 0.5),
                    radius: (1.6 * extent).max(0.12 * size.y),
                    strength: fade(bottom),
                });
            }
        }
        if feet.is_empty() {
            feet.push(Blob {
                centre: Vec3::new((low.x + high.x) * 0.5, plane.height, (low.z + high.z) * 0.5),
                radius: 0.6 * size.x.max(size.z).max(1e-3),
                strength: fade(low.y),
            });
        }
        blobs.extend(feet.into_iter().filter(|b| b.strength > 0.0));
    }
    blobs
}

fn blob_vertices(blobs: &[Blob]) -> Vec<BlobVertex> {
    let mut vertices = Vec::with_capacity(blobs.len() * 6);
    for blob in blobs {
        let corner = |u: f32, v: f32| BlobVertex {
            position: (blob.centre + Vec3::new((u * 2.0 - 1.0) * blob.radius, 0.0, (v * 2.0 - 1.0) * blob.radius))
                .to_array(),
            uv: [u, v],
            strength: blob.strength,
        };
        vertices.extend([corner(0.0, 0.0), corner(1.0, 0.0), corner(1.0, 1.0)]);
        vertices.extend([corner(0.0, 0.0), corner(1.0, 1.0), corner(0.0, 1.0)]);
    }
    vertices
}

impl TechniqueInfo for BlobShadows {
    fn name(&self) -> &'static str {
        "blob"
    }

    fn shadowed_lights(&self, _options: &RenderOptions, _lights: &[PlannedLight]) -> ShadowedLights {
        ShadowedLights::Primary
    }

    fn about(&self) -> &'static str {
        "a soft round texture on a quad under each caster (seed 001's cheapest shadow)"
    }

    fn bench_variants(&self, options: &RenderOptions) -> Vec<Variant> {
        super::shared::bench_variants(options)
    }
}

impl TechniqueUnit for BlobShadows {
    type Kinds = BlobKinds;
    type Setup = ();
    type Passes = BlobPasses;

    fn plan(&self, _options: &RenderOptions, _lights: &[PlannedLight]) -> Result<PassPlan<BlobKinds>> {
        Ok(plan())
    }

    fn setup(&self, _gpu: &Gpu, _scene: &Scene, options: &RenderOptions) -> Result<Prepared<()>> {
        Ok(Prepared::as_given(options))
    }

    fn make(&self, ctx: BuildContext<'_>, scene: &Scene, _setup: ()) -> Result<BlobPasses> {
        BlobPasses::new(&ctx, scene)
    }
}

/// The blob renderer's own part: the scene's meshes, the blob texture, and this frame's quads.
pub struct BlobPasses {
    tone: ShadowTone,
    plane: ReceiverPlane,
    meshes: SceneMeshes,
    /// Per frame slot, that frame's blob quads, in a buffer kept from frame to frame (none
    /// filled without blobs).
    quads: Vec<ReusedBuffer>,
    // Field order: the set is destroyed before the texture it points at.
    blob_set: DescriptorSet,
    _texture: Texture,
}

impl BlobPasses {
    fn new(ctx: &BuildContext, scene: &Scene) -> Result<Self> {
        let gpu = ctx.gpu;
        let plane = receiver_plane(scene, ctx.options.planar.plane.as_ref())?;
        if !plane.is_horizontal() {
            return Err(Error::InvalidInput(
                "blob shadows lie on a horizontal ground: a tilted --plane-normal is for planar and shadow-texture"
                    .into(),
            ));
        }
        let meshes = SceneMeshes::upload(gpu, scene, ctx.options.skinning)?;
        let sampler = Sampler::new(gpu, vk::Filter::LINEAR, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let texture = Texture::from_rgba8(
            gpu,
            "blob",
            &blob_image(BLOB_TEXTURE_SIZE),
            vk::Format::R8G8B8A8_UNORM,
            true,
            sampler,
        )?;
        let blob_set = DescriptorSet::new(
            gpu,
            &[Binding::Texture {
                view: texture.image.view,
                sampler: texture.sampler.raw,
                layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                stages: vk::ShaderStageFlags::FRAGMENT,
            }],
        )?;
        Ok(BlobPasses { tone: ctx.options.shadow_tone, plane, meshes, quads: Vec::new(), blob_set, _texture: texture })
    }
}

impl Passes<BlobKinds> for BlobPasses {
    fn set(&self, set: BlobSet) -> Option<&DescriptorSet> {
        match set {
            BlobSet::BlobTexture => Some(&self.blob_set),
        }
    }

    fn meshes(&self) -> Option<&GpuScene> {
        Some(&self.meshes.meshes)
    }

    fn draw(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draw: BlobDraw,
        pass: &PlannedPass<BlobKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        match draw {
            BlobDraw::Scene => self.meshes.draw_scene(rec, scene, &self.plane, pass, pipelines, 1.0),
            BlobDraw::Quads => {
                if let Some((quads, vertex_count)) = self.quads.get(rec.slot()).and_then(ReusedBuffer::filled) {
                    rec.bind_vertices(quads);
                    rec.draw(vertex_count, 1, 0, 0);
                }
                Ok(())
            }
        }
    }

    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()> {
        self.meshes.follow_pose(&renderer.gpu, scene, renderer.slot())?;
        let darkness = 1.0 - self.tone.darkest_factor();
        let vertices = if light_reaches_plane(&scene.light(), &self.plane.plane) {
            blob_vertices(&blobs(scene, &self.plane, darkness))
        } else {
            Vec::new()
        };
        // The frame that last used this slot has finished: its buffer is free.
        let new = || Ok(ReusedBuffer::new("blob quads", vk::BufferUsageFlags::VERTEX_BUFFER));
        slot_copy(&mut self.quads, renderer.slot(), new)?.fill(&renderer.gpu, &vertices)
    }

    fn writes_per_slot(&self) -> bool {
        true
    }

    /// Its plan names its skinned scene pipeline itself (`lit_scene_pass`).
    fn skinned_twins(&self) -> bool {
        false
    }

    fn stats(&mut self, _output: &FrameOutput, _scene: &Scene) -> Box<dyn FrameStats> {
        Box::new(PlanarStats::of(&self.plane, &self.meshes, self.tone))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_blob_is_dark_in_the_middle_and_clear_at_the_rim() {
        let image = blob_image(BLOB_TEXTURE_SIZE);
        let half = BLOB_TEXTURE_SIZE / 2;
        assert_eq!(image.get_pixel(half, half)[3], 255);
        assert!(image.get_pixel(0, half)[3] < 4, "{:?}", image.get_pixel(0, half));
        assert_eq!(image.get_pixel(0, 0)[3], 0);
        assert_eq!(BLOB_LAYOUT.stride() as usize, std::mem::size_of::<BlobVertex>());
    }
}
