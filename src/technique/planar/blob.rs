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

use std::sync::Arc;

use ash::vk;
use glam::{Vec2, Vec3};

use super::lit_descs;
use super::{light_reaches_plane, receiver_plane, stats, PlanarFrame, ReceiverPlane, SceneMeshes};
use crate::error::Result;
use crate::frame::{RgbaImage, StencilMode};
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::Buffer;
use crate::gpu::texture::{Sampler, Texture};
use crate::gpu::Gpu;
use crate::pipeline::{
    BlendEquation, BlendState, DepthState, FixedFunction, Pipeline, PipelineDesc, RasterState, VertexAttribute,
    VertexLayout,
};
use crate::render::{FrameUniforms, Renderer};
use crate::scene::{bounds_of, Scene};

use crate::technique::lit::ObjectPush;

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
    let mut pixels = Vec::with_capacity((size * size * 4) as usize);
    for y in 0..size {
        for x in 0..size {
            let p = (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / size as f32) * 2.0 - Vec2::ONE;
            let t = ((1.0 - p.length()) / 0.6).clamp(0.0, 1.0);
            let coverage = (t * t * (3.0 - 2.0 * t) * 255.0).round() as u8;
            pixels.extend_from_slice(&[coverage, coverage, coverage, coverage]);
        }
    }
    RgbaImage { width: size, height: size, pixels }
}

pub fn blob_desc() -> PipelineDesc {
    PipelineDesc {
        name: "blob shadow",
        vertex_shader: "planar_blob.vert",
        fragment_shader: "planar_blob.frag",
        vertex_layout: BLOB_LAYOUT,
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster: RasterState { depth_bias: Some(super::SHADOW_BIAS), ..RasterState::CULL_NONE },
            depth: DepthState { compare: Some(vk::CompareOp::LESS_OR_EQUAL), write: false },
            stencil: None,
            blend: BlendState {
                colour: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::SRC_COLOR)),
                alpha: None,
                write_mask: super::RGB_ONLY,
            },
        },
        push_constant_bytes: 0,
        subpass: 0,
    }
}

/// Every pipeline of the technique (for `nostencil passes`).
pub fn pipeline_descs() -> Vec<PipelineDesc> {
    let mut descs = lit_descs().to_vec();
    descs.push(blob_desc());
    descs
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

pub struct BlobRenderer<'s> {
    gpu: Arc<Gpu>,
    scene: &'s Scene,
    shadow_factor: u8,
    renderer: Renderer,
    meshes: SceneMeshes,
    plane: ReceiverPlane,
    scene_pipeline: Pipeline,
    scene_skinned: Pipeline,
    blob: Pipeline,
    // Field order: the set is destroyed before the texture it points at.
    blob_set: DescriptorSet,
    _texture: Texture,
}

impl<'s> BlobRenderer<'s> {
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
        let render_pass = renderer.targets.render_pass;
        let [scene_desc, skinned_desc] = lit_descs();
        let scene_pipeline = Pipeline::new(gpu, &scene_desc, render_pass, &[renderer.frame.layout])?;
        let scene_skinned = Pipeline::new(
            gpu,
            &skinned_desc,
            render_pass,
            &[renderer.frame.layout, meshes.template.descriptors.layout],
        )?;
        let blob = Pipeline::new(gpu, &blob_desc(), render_pass, &[renderer.frame.layout, blob_set.layout])?;
        Ok(BlobRenderer {
            gpu: gpu.clone(),
            scene,
            shadow_factor,
            renderer,
            meshes,
            plane,
            scene_pipeline,
            scene_skinned,
            blob,
            blob_set,
            _texture: texture,
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
        crate::technique::check_same_scene(self.scene, scene, "blob")?;
        self.meshes.update_palettes(scene)?;
        let uniforms = FrameUniforms::for_scene(scene, self.renderer.aspect());
        let darkness = 1.0 - self.shadow_factor as f32 / 255.0;
        let vertices = if light_reaches_plane(&scene.light, self.plane.height) {
            blob_vertices(&blobs(scene, &self.plane, darkness))
        } else {
            Vec::new()
        };
        let quads = if vertices.is_empty() {
            None
        } else {
            Some(Buffer::with_data(&self.gpu, "blob quads", &vertices, vk::BufferUsageFlags::VERTEX_BUFFER)?)
        };
        let clear = scene.background.extend(1.0).to_array();
        let (meshes, scene_pipeline, scene_skinned, blob, set) =
            (&self.meshes, &self.scene_pipeline, &self.scene_skinned, &self.blob, self.blob_set.set);
        let output = self.renderer.render(&uniforms, clear, |rec| {
            rec.pass("scene", |rec| {
                for (index, object) in scene.objects.iter().enumerate() {
                    let push = ObjectPush { model: object.transform, colour: object.colour.extend(1.0) };
                    meshes.draw(rec, scene, index, scene_pipeline, scene_skinned, &push);
                }
                Ok(())
            })?;
            rec.pass("blob shadow", |rec| {
                if let Some(quads) = &quads {
                    super::bind_set1(rec, blob, set);
                    rec.draw_vertices(quads, vertices.len() as u32);
                }
                Ok(())
            })
        })?;
        Ok(PlanarFrame { output, stats: stats(&self.plane, &self.meshes, self.shadow_factor) })
    }
}

/// Renders `scene` with blob shadows.
pub fn render(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    width: u32,
    height: u32,
    stencil: StencilMode,
    shadow_factor: u8,
) -> Result<PlanarFrame> {
    BlobRenderer::new(gpu, scene, width, height, stencil, shadow_factor)?.frame()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_blob_is_dark_in_the_middle_and_clear_at_the_rim() {
        let image = blob_image(BLOB_TEXTURE_SIZE);
        let half = BLOB_TEXTURE_SIZE / 2;
        assert_eq!(image.pixel(half, half)[3], 255);
        assert!(image.pixel(0, half)[3] < 4, "{:?}", image.pixel(0, half));
        assert_eq!(image.pixel(0, 0)[3], 0);
        assert_eq!(BLOB_LAYOUT.stride() as usize, std::mem::size_of::<BlobVertex>());
    }
}
