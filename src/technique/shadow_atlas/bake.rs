//! Per model: the shadow texture and its targets, and the recording of its bake (triangles at
//! their atlas UVs, compared against the shadow map), dilation (texels no triangle covered take
//! their nearest chart's value) and mips (blits).

use std::sync::Arc;

use ash::vk;
use glam::Vec4;

use super::atlas::MeshAtlas;
use super::targets::{self, Framebuffer, ImageView, RenderPass};
use crate::error::{Error, Result};
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::Image;
use crate::gpu::texture::Sampler;
use crate::gpu::Gpu;
use crate::render::Pipeline;
use crate::render::{FrameRecorder, GpuMesh, ObjectPush};
use crate::scene::Scene;

/// One model instance's shadow texture and everything that writes and reads it.
pub struct ObjectShadow {
    pub object: usize,
    pub size: u32,
    pub mip_levels: u32,
    dilate_radius: u32,
    // Field order is drop order: sets and framebuffers before the views and images.
    pub scene_set: DescriptorSet,
    pub dilate_set: DescriptorSet,
    bake_framebuffer: Framebuffer,
    dilate_framebuffer: Framebuffer,
    _mip0: ImageView,
    _raw: Image,
    pub texture: Image,
}

impl ObjectShadow {
    fn extent(&self) -> vk::Extent2D {
        vk::Extent2D { width: self.size, height: self.size }
    }
}

/// Every model's shadow texture, with the render passes of the bake and the dilation.
pub struct AtlasTargets {
    pub objects: Vec<ObjectShadow>,
    pub bake_pass: RenderPass,
    pub dilate_pass: RenderPass,
    _trilinear: Sampler,
    _nearest: Sampler,
}

impl AtlasTargets {
    pub fn new(gpu: &Arc<Gpu>, scene: &Scene, layouts: &[MeshAtlas]) -> Result<Self> {
        let bake_pass = targets::colour_render_pass(gpu, true, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)?;
        let dilate_pass = targets::colour_render_pass(gpu, false, vk::ImageLayout::TRANSFER_DST_OPTIMAL)?;
        let trilinear = Sampler::new(gpu, vk::Filter::LINEAR, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let nearest = Sampler::new(gpu, vk::Filter::NEAREST, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let objects = scene
            .objects
            .iter()
            .enumerate()
            .map(|(index, object)| {
                let layout = layouts.get(object.mesh).ok_or_else(|| {
                    Error::Internal(format!("object '{}' has no atlas for mesh {}", object.name, object.mesh))
                })?;
                let extent = vk::Extent2D { width: layout.size, height: layout.size };
                let name = format!("shadow texture of '{}'", object.name);
                let raw = targets::shadow_texture_image(gpu, &format!("{name} (bake)"), layout.size, 1)?;
                let texture = targets::shadow_texture_image(gpu, &name, layout.size, layout.mip_levels)?;
                let mip0 = ImageView::mip(gpu, &texture, 0)?;
                let texture_binding = |view, sampler: &Sampler| Binding::Texture {
                    view,
                    sampler: sampler.raw,
                    layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    stages: vk::ShaderStageFlags::FRAGMENT,
                };
                Ok(ObjectShadow {
                    object: index,
                    size: layout.size,
                    mip_levels: layout.mip_levels,
                    dilate_radius: layout.dilate_radius,
                    scene_set: DescriptorSet::new(gpu, &[texture_binding(texture.view, &trilinear)])?,
                    dilate_set: DescriptorSet::new(gpu, &[texture_binding(raw.view, &nearest)])?,
                    bake_framebuffer: Framebuffer::new(gpu, &bake_pass, raw.view, extent)?,
                    dilate_framebuffer: Framebuffer::new(gpu, &dilate_pass, mip0.raw, extent)?,
                    _mip0: mip0,
                    _raw: raw,
                    texture,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        if objects.is_empty() {
            return Err(Error::InvalidInput(format!("scene '{}' has no objects", scene.name)));
        }
        Ok(AtlasTargets { objects, bake_pass, dilate_pass, _trilinear: trilinear, _nearest: nearest })
    }

    /// Each model drawn where the light sees it into its raw bake, lit or shadowed per texel:
    /// `draws` holds each one's mesh and pipeline (the bake or its skinned twin, which share
    /// the layout `sets` are bound for: the frame's and the lights').
    pub fn record_bake(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draws: &[(&GpuMesh, &Pipeline)],
        sets: &[vk::DescriptorSet],
    ) {
        // Alpha 0: no triangle covers the texel (yet).
        let clear = [vk::ClearValue { color: vk::ClearColorValue { float32: [1.0, 1.0, 1.0, 0.0] } }];
        for (o, (mesh, bake)) in self.objects.iter().zip(draws) {
            let object = &scene.objects[o.object];
            rec.begin_offscreen_pass(&self.bake_pass, o.bake_framebuffer.raw, o.extent(), &clear);
            rec.bind_with_sets(bake, sets);
            rec.push(bake, &ObjectPush { model: object.transform, colour: Vec4::ONE });
            rec.draw_mesh(mesh);
            rec.end_render_pass();
        }
    }

    /// Each raw bake dilated into mip 0 of its shadow texture.
    pub fn record_dilate(&self, rec: &mut FrameRecorder, dilate: &Pipeline) {
        for o in &self.objects {
            rec.begin_offscreen_pass(&self.dilate_pass, o.dilate_framebuffer.raw, o.extent(), &[]);
            rec.bind_with_sets(dilate, &[o.dilate_set.set]);
            rec.push(dilate, &[o.dilate_radius as i32, 0, 0, 0]);
            rec.draw(3, 1, 0, 0);
            rec.end_render_pass();
        }
    }

    /// Each shadow texture's mips from its mip 0, left ready for sampling.
    pub fn record_mips(&self, rec: &mut FrameRecorder) {
        for o in &self.objects {
            rec.build_mips(o.texture.raw, o.size, o.mip_levels);
        }
    }
}
