//! The scene's materials on the GPU: each texture uploaded once (sRGB, full mip chain, the
//! glTF sampler), and per material a small uniform buffer with its two textures in one
//! descriptor set (`shaders/material.glsl`), bound at [`MATERIAL_SET`] per draw.

use std::sync::Arc;

use ash::vk;
use glam::{Mat3, Vec4};
use image::RgbaImage;

use crate::error::{Error, Result};
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::Buffer;
use crate::gpu::texture::{can_blit_mips, Sampler, Texture};
use crate::gpu::Gpu;
use crate::scene::model::{AlphaMode, Filter, Material, TextureRef, TextureRgba8, Wrap};
use crate::scene::Scene;

/// The descriptor set index of the material in every pipeline that shades with it (set 0 is
/// the frame's uniforms; a technique's own sets follow the material).
pub const MATERIAL_SET: u32 = 1;

/// A pipeline bound only for objects whose material needs it (see
/// [`PlannedPass::or_variant`](crate::render::plan::PlannedPass::or_variant)).
/// Scene passes: MASK cuts texels out (a `discard` the opaque pipeline keeps out of its shader,
/// so it keeps early depth on a tiler), double-sided draws both faces with the normal turned to
/// the viewer, BLEND is drawn after everything opaque, back to front, without depth writes.
/// Shadow-casting passes need only `Masked`: a blended caster casts as if opaque.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MaterialVariant {
    Masked,
    DoubleSided,
    Blend,
    BlendDoubleSided,
}

impl MaterialVariant {
    /// What a scene (shading) pass draws `material` with; `None`: the pass's opaque pipeline.
    pub fn for_surface(material: &Material) -> Option<Self> {
        match (material.alpha_mode, material.double_sided) {
            (AlphaMode::Blend, true) => Some(MaterialVariant::BlendDoubleSided),
            (AlphaMode::Blend, false) => Some(MaterialVariant::Blend),
            (_, true) => Some(MaterialVariant::DoubleSided),
            (AlphaMode::Mask { .. }, false) => Some(MaterialVariant::Masked),
            (AlphaMode::Opaque, false) => None,
        }
    }

    /// What a shadow-casting pass draws `material` with (casters are drawn without culling).
    pub fn for_caster(material: &Material) -> Option<Self> {
        matches!(material.alpha_mode, AlphaMode::Mask { .. }).then_some(MaterialVariant::Masked)
    }
}

/// Mirrors `MaterialUniforms` in `shaders/material.glsl` (std140).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MaterialUniforms {
    /// Linear RGBA factor.
    pub base_colour: Vec4,
    /// rgb: linear factor; a unused.
    pub emissive: Vec4,
    /// Rows of the base colour texture's 2x3 UV transform (KHR_texture_transform).
    pub base_uv: [Vec4; 2],
    /// Rows of the emissive texture's UV transform.
    pub emissive_uv: [Vec4; 2],
    /// x: alpha cutoff (MASK; below 0 for OPAQUE and BLEND, so nothing is cut), y: unlit (0/1),
    /// z: UV set of the base colour texture, w: UV set of the emissive texture.
    pub params: Vec4,
}

impl MaterialUniforms {
    pub fn of(material: &Material) -> Self {
        let uv_rows = |t: Option<TextureRef>| {
            let m = t.and_then(|t| t.transform).map_or(Mat3::IDENTITY, |t| t.matrix());
            [0, 1].map(|row| Vec4::new(m.x_axis[row], m.y_axis[row], m.z_axis[row], 0.0))
        };
        let set = |t: Option<TextureRef>| t.map_or(0.0, |t| t.tex_coord as f32);
        let cutoff = match material.alpha_mode {
            AlphaMode::Mask { cutoff } => cutoff,
            AlphaMode::Opaque | AlphaMode::Blend => -1.0,
        };
        MaterialUniforms {
            base_colour: material.base_color,
            emissive: material.emissive.extend(0.0),
            base_uv: uv_rows(material.base_color_texture),
            emissive_uv: uv_rows(material.emissive_texture),
            params: Vec4::new(
                cutoff,
                if material.unlit { 1.0 } else { 0.0 },
                set(material.base_color_texture),
                set(material.emissive_texture),
            ),
        }
    }
}

const UNIFORM_BYTES: u64 = std::mem::size_of::<MaterialUniforms>() as u64;
// Mirrors the shaders' std140 block of 112 bytes.
const _: () = assert!(UNIFORM_BYTES == 112);

/// One material's uniforms and descriptor set.
struct GpuMaterial {
    // Field order: the set is destroyed before the buffer it points at.
    set: DescriptorSet,
    _uniforms: Buffer,
}

/// Every material of a scene, ready to bind.
pub struct GpuMaterials {
    // Field order is drop order: sets before the textures they point at.
    materials: Vec<GpuMaterial>,
    /// A plain white material: its layout is every material's (all are defined alike), and it
    /// is bound until a draw binds its object's.
    template: GpuMaterial,
    /// Kept alive for the sets that point at them.
    _textures: Vec<Texture>,
    /// 1x1 white, for "no texture" (the sets point at it).
    _white: Texture,
}

impl GpuMaterials {
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene) -> Result<Self> {
        let mut warnings = Vec::new();
        let white_pixels = RgbaImage::from_pixel(1, 1, image::Rgba([255; 4]));
        let nearest = Sampler::new(gpu, vk::Filter::NEAREST, vk::SamplerAddressMode::REPEAT)?;
        let white = Texture::from_rgba8(gpu, "white", &white_pixels, vk::Format::R8G8B8A8_SRGB, false, nearest)?;
        let textures = scene
            .textures
            .iter()
            .enumerate()
            .map(|(i, t)| upload_texture(gpu, i, t, &mut warnings))
            .collect::<Result<Vec<_>>>()?;
        let make = |name: &str, material: &Material| -> Result<GpuMaterial> {
            let texture = |t: Option<TextureRef>| match t {
                None => Ok(&white),
                Some(t) => textures.get(t.texture).ok_or_else(|| {
                    Error::InvalidInput(format!("material '{name}' names texture {} of {}", t.texture, textures.len()))
                }),
            };
            let (base, emissive) = (texture(material.base_color_texture)?, texture(material.emissive_texture)?);
            let uniforms = Buffer::with_data(
                gpu,
                &format!("material '{name}'"),
                &[MaterialUniforms::of(material)],
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            )?;
            let sampled = |t: &Texture| Binding::Texture {
                view: t.image.view,
                sampler: t.sampler.raw,
                layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                stages: vk::ShaderStageFlags::FRAGMENT,
            };
            let set = DescriptorSet::new(
                gpu,
                &[
                    Binding::UniformBuffer {
                        buffer: uniforms.raw,
                        range: UNIFORM_BYTES,
                        stages: vk::ShaderStageFlags::FRAGMENT,
                    },
                    sampled(base),
                    sampled(emissive),
                ],
            )?;
            Ok(GpuMaterial { set, _uniforms: uniforms })
        };
        let template = make("template", &Material::default())?;
        let materials = scene
            .materials
            .iter()
            .enumerate()
            .map(|(i, m)| make(&m.name.clone().unwrap_or_else(|| format!("material {i}")), m))
            .collect::<Result<Vec<_>>>()?;
        for warning in &warnings {
            eprintln!("nostencil: warning: {warning}");
        }
        Ok(GpuMaterials { materials, template, _textures: textures, _white: white })
    }

    /// The layout of every material's set.
    pub fn layout(&self) -> vk::DescriptorSetLayout {
        self.template.set.layout
    }

    /// The set bound before any object's (a white opaque material).
    pub fn template_set(&self) -> vk::DescriptorSet {
        self.template.set.set
    }

    /// Material `index`'s set (the template's for an index out of range).
    pub fn set(&self, index: usize) -> vk::DescriptorSet {
        self.materials.get(index).map_or(self.template.set.set, |m| m.set.set)
    }
}

/// Uploads texture `index`: sRGB-encoded texels as R8G8B8A8_SRGB (the sampler decodes them),
/// with a full mip chain when its sampler mipmaps and the format can be blitted linearly.
fn upload_texture(gpu: &Arc<Gpu>, index: usize, texture: &TextureRgba8, warnings: &mut Vec<String>) -> Result<Texture> {
    let name = texture.name.clone().unwrap_or_else(|| format!("texture {index}"));
    let side = crate::gpu::mobile_profile::MAX_IMAGE_SIDE;
    if texture.width == 0 || texture.height == 0 || texture.width > side || texture.height > side {
        return Err(Error::InvalidInput(format!(
            "texture '{name}' is {}x{}; the mobile profile's images are 1 to {side} texels a side",
            texture.width, texture.height
        )));
    }
    let format = if texture.srgb { vk::Format::R8G8B8A8_SRGB } else { vk::Format::R8G8B8A8_UNORM };
    let pixels = RgbaImage::from_raw(texture.width, texture.height, texture.pixels.clone()).ok_or_else(|| {
        Error::InvalidInput(format!(
            "texture '{name}': {} bytes for {}x{} RGBA8",
            texture.pixels.len(),
            texture.width,
            texture.height
        ))
    })?;
    let mut mipmaps = texture.sampler.mipmap_filter.is_some();
    if mipmaps && !can_blit_mips(gpu, format) {
        warnings.push(format!(
            "texture '{name}': the device cannot blit {format:?} linearly, so it is sampled without mipmaps"
        ));
        mipmaps = false;
    }
    let sampler = Sampler::from_info(gpu, sampler_info(&texture.sampler, mipmaps))?;
    Texture::from_rgba8(gpu, &name, &pixels, format, mipmaps, sampler)
}

/// The Vulkan sampler of a glTF sampler: its filters, mipmap mode and wraps; without mipmaps
/// only the base level is read (max LOD 0).
pub fn sampler_info(sampler: &crate::scene::model::Sampler, mipmaps: bool) -> vk::SamplerCreateInfo<'static> {
    let filter = |f: Filter| match f {
        Filter::Nearest => vk::Filter::NEAREST,
        Filter::Linear => vk::Filter::LINEAR,
    };
    let wrap = |w: Wrap| match w {
        Wrap::Repeat => vk::SamplerAddressMode::REPEAT,
        Wrap::MirroredRepeat => vk::SamplerAddressMode::MIRRORED_REPEAT,
        Wrap::ClampToEdge => vk::SamplerAddressMode::CLAMP_TO_EDGE,
    };
    let mipmap_mode = match sampler.mipmap_filter {
        Some(Filter::Linear) => vk::SamplerMipmapMode::LINEAR,
        _ => vk::SamplerMipmapMode::NEAREST,
    };
    vk::SamplerCreateInfo::default()
        .mag_filter(filter(sampler.mag_filter))
        .min_filter(filter(sampler.min_filter))
        .mipmap_mode(mipmap_mode)
        .address_mode_u(wrap(sampler.wrap_s))
        .address_mode_v(wrap(sampler.wrap_t))
        .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .max_lod(if mipmaps { vk::LOD_CLAMP_NONE } else { 0.0 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::model::TextureTransform;
    use glam::{Vec2, Vec3};

    #[test]
    fn uniforms_carry_the_uv_transform_rows_and_the_cutoff() {
        let transform = TextureTransform { offset: Vec2::new(0.5, 0.25), rotation: 0.0, scale: Vec2::new(2.0, 3.0) };
        let material = Material {
            base_color_texture: Some(TextureRef { texture: 0, tex_coord: 1, transform: Some(transform) }),
            alpha_mode: AlphaMode::Mask { cutoff: 0.3 },
            unlit: true,
            ..Material::default()
        };
        let u = MaterialUniforms::of(&material);
        // u' = 2u + 0.5, v' = 3v + 0.25.
        assert_eq!(u.base_uv, [Vec4::new(2.0, 0.0, 0.5, 0.0), Vec4::new(0.0, 3.0, 0.25, 0.0)]);
        assert_eq!(u.emissive_uv, [Vec4::new(1.0, 0.0, 0.0, 0.0), Vec4::new(0.0, 1.0, 0.0, 0.0)]);
        assert_eq!(u.params, Vec4::new(0.3, 1.0, 1.0, 0.0));
        assert_eq!(MaterialUniforms::of(&Material::default()).params.x, -1.0);
        assert_eq!(MaterialUniforms::of(&Material::default()).emissive.truncate(), Vec3::ZERO);
    }

    #[test]
    fn samplers_follow_the_gltf_sampler() {
        use crate::scene::model::Sampler as GltfSampler;
        let gltf = GltfSampler {
            wrap_s: Wrap::ClampToEdge,
            wrap_t: Wrap::MirroredRepeat,
            mag_filter: Filter::Nearest,
            min_filter: Filter::Linear,
            mipmap_filter: Some(Filter::Nearest),
        };
        let info = sampler_info(&gltf, true);
        assert_eq!((info.mag_filter, info.min_filter), (vk::Filter::NEAREST, vk::Filter::LINEAR));
        assert_eq!(info.mipmap_mode, vk::SamplerMipmapMode::NEAREST);
        assert_eq!(
            (info.address_mode_u, info.address_mode_v),
            (vk::SamplerAddressMode::CLAMP_TO_EDGE, vk::SamplerAddressMode::MIRRORED_REPEAT)
        );
        assert_eq!(info.max_lod, vk::LOD_CLAMP_NONE);
        // No mipmap filter (or no mips built): the base level only.
        let flat = GltfSampler { mipmap_filter: None, ..gltf };
        assert_eq!(sampler_info(&flat, false).max_lod, 0.0);
        assert_eq!(sampler_info(&GltfSampler::default(), true).mipmap_mode, vk::SamplerMipmapMode::LINEAR);
    }
}
