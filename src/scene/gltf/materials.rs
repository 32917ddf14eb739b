//! Materials and what they sample: base-colour and emissive textures (their images decoded
//! once, PNG or JPEG) with their samplers and KHR_texture_transform, and the material
//! extensions the renderer honours: KHR_materials_unlit, KHR_materials_pbrSpecularGlossiness
//! (its diffuse becomes the base colour), KHR_materials_emissive_strength, KHR_materials_transmission
//! (accepted, not rendered).

use glam::{Vec2, Vec3, Vec4};
use gltf::json;
use json::validation::Checked;
use serde_json::Value;

use super::loader::{checked, label, Loader};
use crate::error::Result;
use crate::scene::model::{AlphaMode, Filter, Material, Sampler, TextureRef, TextureRgba8, TextureTransform, Wrap};

const SPEC_GLOSS: &str = "KHR_materials_pbrSpecularGlossiness";
const UNLIT: &str = "KHR_materials_unlit";
const TRANSMISSION: &str = "KHR_materials_transmission";
const TEXTURE_TRANSFORM: &str = "KHR_texture_transform";
pub(super) const EMISSIVE_STRENGTH: &str = "KHR_materials_emissive_strength";

/// A textureInfo as the loader needs it, from the typed core field or from extension JSON.
struct TextureInfo<'j> {
    index: usize,
    tex_coord: u32,
    transform: Option<&'j Value>,
}

impl<'j> TextureInfo<'j> {
    fn core(info: &'j json::texture::Info) -> Self {
        TextureInfo {
            index: info.index.value(),
            tex_coord: info.tex_coord,
            transform: info.extensions.as_ref().and_then(|e| e.others.get(TEXTURE_TRANSFORM)),
        }
    }

    /// A textureInfo object inside an extension (such as spec-gloss `diffuseTexture`).
    fn from_json(value: &'j Value) -> std::result::Result<Self, String> {
        let index = value
            .get("index")
            .and_then(Value::as_u64)
            .and_then(|i| usize::try_from(i).ok())
            .ok_or("textureInfo has no valid `index`")?;
        let tex_coord = match value.get("texCoord") {
            None => 0,
            Some(t) => {
                t.as_u64().and_then(|t| u32::try_from(t).ok()).ok_or("textureInfo `texCoord` is not an index")?
            }
        };
        Ok(TextureInfo { index, tex_coord, transform: value.get("extensions").and_then(|e| e.get(TEXTURE_TRANSFORM)) })
    }
}

/// KHR_texture_transform's object: offset, rotation, scale, and an optional texCoord override.
fn texture_transform(value: &Value) -> std::result::Result<(TextureTransform, Option<u32>), String> {
    let pair = |name: &str, default: [f32; 2]| -> std::result::Result<Vec2, String> {
        match value.get(name) {
            None => Ok(Vec2::from_array(default)),
            Some(v) => match v.as_array().map(|a| a.iter().map(Value::as_f64).collect::<Option<Vec<_>>>()) {
                Some(Some(a)) if a.len() == 2 => Ok(Vec2::new(a[0] as f32, a[1] as f32)),
                _ => Err(format!("{TEXTURE_TRANSFORM} `{name}` is {v}, not two numbers")),
            },
        }
    };
    let rotation = match value.get("rotation") {
        None => 0.0,
        Some(v) => v.as_f64().ok_or_else(|| format!("{TEXTURE_TRANSFORM} `rotation` is {v}, not a number"))? as f32,
    };
    let tex_coord = match value.get("texCoord") {
        None => None,
        Some(v) => Some(
            v.as_u64()
                .and_then(|t| u32::try_from(t).ok())
                .ok_or_else(|| format!("{TEXTURE_TRANSFORM} `texCoord` is {v}, not an index"))?,
        ),
    };
    let transform =
        TextureTransform { offset: pair("offset", [0.0, 0.0])?, rotation, scale: pair("scale", [1.0, 1.0])? };
    if !(transform.offset.is_finite() && transform.rotation.is_finite() && transform.scale.is_finite()) {
        return Err(format!("{TEXTURE_TRANSFORM} has a non-finite value"));
    }
    Ok((transform, tex_coord))
}

/// RGBA from an extension's array of four numbers (spec-gloss `diffuseFactor`).
fn vec4_field(ext: &Value, name: &str, default: Vec4) -> std::result::Result<Vec4, String> {
    match ext.get(name) {
        None => Ok(default),
        Some(v) => match v.as_array().map(|a| a.iter().map(Value::as_f64).collect::<Option<Vec<_>>>()) {
            Some(Some(a)) if a.len() == 4 => Ok(Vec4::new(a[0] as f32, a[1] as f32, a[2] as f32, a[3] as f32)),
            _ => Err(format!("`{name}` is {v}, not four numbers")),
        },
    }
}

impl Loader<'_> {
    pub(super) fn materials(&mut self) -> Result<Vec<Material>> {
        let mut out = Vec::with_capacity(self.root.materials.len());
        let mut transmissive = Vec::new();
        for (i, m) in self.root.materials.iter().enumerate() {
            let what = label("material", i, m.name.as_deref());
            let ext = |name: &str| m.extensions.as_ref().and_then(|e| e.others.get(name));
            let pbr = &m.pbr_metallic_roughness;
            let (base_color, base_color_texture) = match ext(SPEC_GLOSS) {
                // The specular-glossiness model's diffuse is what this renderer shades as base
                // colour; its specular and glossiness are not used.
                Some(sg) => {
                    let factor = vec4_field(sg, "diffuseFactor", Vec4::ONE)
                        .map_err(|e| self.fail(format!("{what}: {SPEC_GLOSS} {e}")))?;
                    let texture = match sg.get("diffuseTexture") {
                        None => None,
                        Some(info) => {
                            let info = TextureInfo::from_json(info)
                                .map_err(|e| self.fail(format!("{what}: {SPEC_GLOSS} diffuseTexture: {e}")))?;
                            self.texture_ref(&info, &what, "diffuse texture")?
                        }
                    };
                    (factor, texture)
                }
                None => {
                    let texture = match &pbr.base_color_texture {
                        None => None,
                        Some(info) => self.texture_ref(&TextureInfo::core(info), &what, "base colour texture")?,
                    };
                    (Vec4::from_array(pbr.base_color_factor.0), texture)
                }
            };
            let emissive_texture = match &m.emissive_texture {
                None => None,
                Some(info) => self.texture_ref(&TextureInfo::core(info), &what, "emissive texture")?,
            };
            if ext(TRANSMISSION).is_some() {
                transmissive.push(what.clone());
            }
            let alpha_mode = match checked(&m.alpha_mode) {
                Some(json::material::AlphaMode::Mask) => {
                    AlphaMode::Mask { cutoff: m.alpha_cutoff.map_or(0.5, |c| c.0) }
                }
                Some(json::material::AlphaMode::Blend) => AlphaMode::Blend,
                _ => AlphaMode::Opaque,
            };
            out.push(Material {
                name: m.name.clone(),
                base_color,
                base_color_texture,
                metallic: pbr.metallic_factor.0,
                roughness: pbr.roughness_factor.0,
                emissive: Vec3::from_array(m.emissive_factor.0) * self.emissive_strength(ext(EMISSIVE_STRENGTH), &what),
                emissive_texture,
                alpha_mode,
                double_sided: m.double_sided,
                unlit: ext(UNLIT).is_some(),
            });
        }
        if !transmissive.is_empty() {
            self.warnings.push(format!(
                "{TRANSMISSION} is not rendered: {} drawn with their base colour alone",
                transmissive.join(", ")
            ));
        }
        Ok(out)
    }

    /// KHR_materials_emissive_strength's factor (1 without it). The frame is 8-bit, so emissive
    /// light above 1 saturates: the strength still scales a dim emissive factor up as authored.
    fn emissive_strength(&mut self, extension: Option<&Value>, what: &str) -> f32 {
        let Some(extension) = extension else { return 1.0 };
        match extension.get("emissiveStrength") {
            None => 1.0,
            Some(v) => match v.as_f64() {
                Some(strength) if strength >= 0.0 && strength.is_finite() => strength as f32,
                _ => {
                    self.warnings.push(format!(
                        "{what}: {EMISSIVE_STRENGTH} emissiveStrength {v} is not a number >= 0; 1 is used"
                    ));
                    1.0
                }
            },
        }
    }

    /// A texture reference of material `what` (`slot` says which of its textures), with its
    /// KHR_texture_transform; `None` (with a warning) when the texture cannot be shown.
    fn texture_ref(&mut self, info: &TextureInfo, what: &str, slot: &str) -> Result<Option<TextureRef>> {
        let (transform, tex_coord) = match info.transform {
            None => (None, info.tex_coord),
            Some(value) => {
                let (transform, tex_coord) =
                    texture_transform(value).map_err(|e| self.fail(format!("{what} {slot}: {e}")))?;
                (Some(transform), tex_coord.unwrap_or(info.tex_coord))
            }
        };
        if tex_coord > 1 {
            self.warnings
                .push(format!("{what}: {slot} uses TEXCOORD_{tex_coord}; only 0 and 1 are loaded, texture dropped"));
            return Ok(None);
        }
        let user = format!("{what} {slot}");
        Ok(self.texture(info.index, &user)?.map(|texture| TextureRef { texture, tex_coord, transform }))
    }

    /// Decodes glTF texture `index` (once) and returns its slot in `Model::textures`, or
    /// `None` with a warning if it has no PNG or JPEG image.
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
        // gltf-json's mark for a texture without `source` (its image comes from an extension).
        if image_index == u32::MAX as usize {
            let sources: Vec<&str> = tex.extensions.iter().flat_map(|e| e.others.keys()).map(String::as_str).collect();
            let why = if sources.is_empty() {
                "has no image (no `source`)".to_string()
            } else {
                format!("has its image only through {}, which is not decoded", sources.join(", "))
            };
            self.warnings.push(format!("texture {index} ({user}) {why}; the material uses its factor alone"));
            self.texture_slots.insert(index, None);
            return Ok(None);
        }
        let image = self
            .root
            .images
            .get(image_index)
            .ok_or_else(|| self.fail(format!("texture {index}: image {image_index} does not exist")))?;
        let what = format!("texture {index} image {image_index}");
        let bytes: Vec<u8> = match (&image.uri, image.buffer_view) {
            (_, Some(view)) => self.buffers.view(view.value()).map_err(|e| self.fail(format!("{what}: {e}")))?.to_vec(),
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
                let decoded = decode_image(&bytes, format)
                    .map_err(|e| match e {
                        image::ImageError::Limits(_) => self.fail(format!(
                            "{what}: {name} is larger than the mobile profile's {side}x{side} texels (or needs more \
                             than {MAX_DECODE_BYTES} bytes to decode); not decoded",
                            side = crate::gpu::mobile_profile::MAX_IMAGE_SIDE
                        )),
                        e => self.fail(format!("{what}: {name} does not decode: {e}")),
                    })?
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
                     uses its factor alone"
                ));
                None
            }
        };
        self.texture_slots.insert(index, slot);
        Ok(slot)
    }
}

/// Decodes PNG or JPEG bytes, refusing from the header alone an image larger than the mobile
/// profile's textures (`MAX_IMAGE_SIDE` a side, which the renderer would refuse anyway), so that
/// a few bytes claiming 60000x60000 texels are never allocated for; `MAX_DECODE_BYTES` bounds
/// the decoder's own buffers as well.
fn decode_image(bytes: &[u8], format: image::ImageFormat) -> image::ImageResult<image::DynamicImage> {
    let side = crate::gpu::mobile_profile::MAX_IMAGE_SIDE;
    let mut reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(side);
    limits.max_image_height = Some(side);
    limits.max_alloc = Some(MAX_DECODE_BYTES);
    reader.limits(limits);
    reader.decode()
}

/// Twice a 4096x4096 RGBA8 image: the decoded pixels and a conversion of them.
const MAX_DECODE_BYTES: u64 = 2 * 4096 * 4096 * 4;

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
