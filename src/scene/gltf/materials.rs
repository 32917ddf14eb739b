//! Materials and what they sample: base-colour textures (their images decoded once, PNG or
//! JPEG) and samplers.

use glam::{Vec3, Vec4};
use gltf::json;
use json::validation::Checked;

use super::{checked, label, Loader};
use crate::scene::model::{AlphaMode, Filter, Material, Sampler, TextureRef, TextureRgba8, Wrap};
use crate::Result;

impl Loader<'_> {
    pub(super) fn materials(&mut self) -> Result<Vec<Material>> {
        let mut out = Vec::with_capacity(self.root.materials.len());
        for (i, m) in self.root.materials.iter().enumerate() {
            let what = label("material", i, m.name.as_deref());
            let pbr = &m.pbr_metallic_roughness;
            let base_color_texture = match &pbr.base_color_texture {
                None => None,
                Some(info) if info.tex_coord > 1 => {
                    self.warnings.push(format!(
                        "{what}: base colour texture uses TEXCOORD_{}; only 0 and 1 are loaded, \
                         texture dropped",
                        info.tex_coord
                    ));
                    None
                }
                Some(info) => self.texture(info.index.value(), &what)?.map(|texture| TextureRef {
                    texture,
                    tex_coord: info.tex_coord,
                    transform: None,
                }),
            };
            let alpha_mode = match checked(&m.alpha_mode) {
                Some(json::material::AlphaMode::Mask) => {
                    AlphaMode::Mask { cutoff: m.alpha_cutoff.map_or(0.5, |c| c.0) }
                }
                Some(json::material::AlphaMode::Blend) => AlphaMode::Blend,
                _ => AlphaMode::Opaque,
            };
            out.push(Material {
                name: m.name.clone(),
                base_color: Vec4::from_array(pbr.base_color_factor.0),
                base_color_texture,
                metallic: pbr.metallic_factor.0,
                roughness: pbr.roughness_factor.0,
                emissive: Vec3::from_array(m.emissive_factor.0),
                emissive_texture: None,
                alpha_mode,
                double_sided: m.double_sided,
                unlit: false,
            });
        }
        Ok(out)
    }

    /// Decodes glTF texture `index` (once) and returns its slot in `Model::textures`, or
    /// `None` with a warning if its image is not PNG.
    fn texture(&mut self, index: usize, user: &str) -> Result<Option<usize>> {
        if let Some(slot) = self.texture_slots.get(&index) {
            return Ok(*slot);
        }
        let tex = self
            .root
            .textures
            .get(index)
            .ok_or_else(|| self.fail(format!("{user}: texture {index} does not exist")))?;
        let image_index = tex.source.value();
        let image = self
            .root
            .images
            .get(image_index)
            .ok_or_else(|| self.fail(format!("texture {index}: image {image_index} does not exist")))?;
        let what = format!("texture {index} image {image_index}");
        let bytes: Vec<u8> = match (&image.uri, image.buffer_view) {
            (_, Some(view)) => super::buffers::view_bytes(self.root, self.buffers, view.value())
                .map_err(|e| self.fail(format!("{what}: {e}")))?
                .to_vec(),
            (Some(uri), None) => match super::buffers::decode_data_uri(uri) {
                Some(decoded) => decoded.map_err(|e| self.fail(format!("{what}: {e}")))?,
                None => {
                    super::buffers::read_external(&self.path, uri).map_err(|e| self.fail(format!("{what}: {e}")))?
                }
            },
            (None, None) => return Err(self.fail(format!("{what} has neither a uri nor a bufferView"))),
        };
        // glTF core allows PNG and JPEG; other formats arrive through extensions (WebP,
        // KTX2/Basis) that this renderer does not read, so those materials fall back to their
        // base colour factor with a warning rather than failing the whole file.
        let slot = match core_image_format(&bytes) {
            Some((format, name)) => {
                let decoded = image::load_from_memory_with_format(&bytes, format)
                    .map_err(|e| self.fail(format!("{what}: {name} does not decode: {e}")))?
                    .to_rgba8();
                let sampler = match tex.sampler {
                    Some(s) => {
                        let s = self.root.samplers.get(s.value()).ok_or_else(|| {
                            self.fail(format!("texture {index}: sampler {} does not exist", s.value()))
                        })?;
                        sampler(s)
                    }
                    None => Sampler::default(),
                };
                self.textures.push(TextureRgba8 {
                    name: tex.name.clone().or_else(|| image.name.clone()),
                    width: decoded.width(),
                    height: decoded.height(),
                    pixels: decoded.into_raw(),
                    srgb: true,
                    sampler,
                });
                Some(self.textures.len() - 1)
            }
            None => {
                let format = if bytes.get(8..12) == Some(b"WEBP") {
                    "WebP"
                } else if bytes.starts_with(b"\xABKTX 20\xBB") {
                    "KTX2"
                } else {
                    "neither PNG nor JPEG"
                };
                self.warnings.push(format!(
                    "{what} ({user}) is {format}; glTF core images are PNG or JPEG, so the material \
                     uses its base colour factor alone"
                ));
                None
            }
        };
        self.texture_slots.insert(index, slot);
        Ok(slot)
    }
}

/// The image format of glTF core image bytes, told by their signature (a `mimeType` may be
/// absent or wrong in real files; the bytes are not).
fn core_image_format(bytes: &[u8]) -> Option<(image::ImageFormat, &'static str)> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        Some((image::ImageFormat::Png, "PNG"))
    } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
        Some((image::ImageFormat::Jpeg, "JPEG"))
    } else {
        None
    }
}

fn sampler(s: &json::texture::Sampler) -> Sampler {
    use json::texture::{MagFilter, MinFilter, WrappingMode};
    let wrap = |w: &Checked<WrappingMode>| match checked(w) {
        Some(WrappingMode::ClampToEdge) => Wrap::ClampToEdge,
        Some(WrappingMode::MirroredRepeat) => Wrap::MirroredRepeat,
        _ => Wrap::Repeat,
    };
    let mag_filter = match s.mag_filter.as_ref().and_then(checked) {
        Some(MagFilter::Nearest) => Filter::Nearest,
        _ => Filter::Linear,
    };
    let (min_filter, mipmap_filter) = match s.min_filter.as_ref().and_then(checked) {
        Some(MinFilter::Nearest) => (Filter::Nearest, None),
        Some(MinFilter::Linear) => (Filter::Linear, None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, Some(Filter::Nearest)),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, Some(Filter::Nearest)),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, Some(Filter::Linear)),
        Some(MinFilter::LinearMipmapLinear) | None => (Filter::Linear, Some(Filter::Linear)),
    };
    Sampler { wrap_s: wrap(&s.wrap_s), wrap_t: wrap(&s.wrap_t), mag_filter, min_filter, mipmap_filter }
}
