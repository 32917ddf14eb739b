//! glTF 2.0 (`.gltf` with external or data-URI buffers, and `.glb`) into a `Model`.
//!
//! The gltf crate parses and validates the JSON (references, enums, required fields); the
//! bytes are read by `gltf_data` with checked offsets. On top of that the loader checks what the
//! renderer relies on: attribute types and counts, indices in range, finite positions, key
//! times strictly increasing, skins of at most `MAX_JOINTS` joints, and joint indices inside
//! their skin. Every failure is an `Error::Asset` naming the file and the offending element;
//! things that can be skipped or repaired go to `Model::warnings` instead.
//!
//! Decisions:
//! - Skin weights are renormalised to sum 1 (exporters often write sums a little under 1).
//!   A vertex whose weights are all zero gets weight 1 on its first joint slot (JOINTS_0.x), as
//!   three.js does: it then follows that joint (usually the root) instead of collapsing to the
//!   origin, and the GPU format stays 4 joints + 4 weights into a palette of at most
//!   `MAX_JOINTS` matrices, with no identity entry reserved for "the mesh node itself". The
//!   glTF spec forbids all-zero weights, so this only repairs invalid files, with a warning.
//! - A joint index outside the skin is an error if its weight is nonzero; with weight zero it
//!   is replaced by 0 (so the GPU never reads past the palette) and noted in the warnings.
//! - Missing normals are computed smooth (welded by position, area-weighted).
//! - Only base-colour textures are decoded, and only PNG; a texture in another format is
//!   dropped with a warning and the material keeps its base-colour factor.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Mat4, Quat, Vec2, Vec3, Vec4};
use gltf::json;
use json::accessor::{ComponentType as C, Type as T};
use json::validation::Checked;

use super::gltf_data::{self, Dense, Problem};
use super::model::{
    AlphaMode, Animation, Camera, Channel, ChannelValues, Filter, Interpolation, Light, LightKind, Material, Mesh,
    Model, Node, Primitive, Projection, Property, Sampler, Skin, TextureRef, TextureRgba8, Transform, Wrap, MAX_JOINTS,
};
use super::normals::smooth_normals;
use crate::{Error, Result};

/// Component types glTF allows for float attributes stored as normalised integers.
const FLOAT_OR_UNORM: &[C] = &[C::F32, C::U8, C::U16];
const FLOAT_OR_NORM: &[C] = &[C::F32, C::I8, C::U8, C::I16, C::U16];
/// Normals under KHR_mesh_quantization: float or normalised signed integers.
const FLOAT_OR_SNORM: &[C] = &[C::F32, C::I8, C::I16];

/// Extensions this loader honours when a file lists them as required; any other required
/// extension changes what the data means (compressed or transformed), so such a file is refused.
const SUPPORTED_REQUIRED_EXTENSIONS: &[&str] = &["KHR_lights_punctual", "KHR_mesh_quantization"];

/// Loads a `.gltf` or `.glb` file. External buffers and images are resolved relative to it.
pub fn load_gltf(path: &Path) -> Result<Model> {
    let bytes = std::fs::read(path)
        .map_err(|e| Error::Asset { path: path.to_path_buf(), problem: format!("cannot read the file: {e}") })?;
    load_gltf_slice(&bytes, path)
}

/// Loads glTF from memory; `path` names the file in errors and anchors relative URIs.
pub fn load_gltf_slice(bytes: &[u8], path: &Path) -> Result<Model> {
    let asset = |problem: Problem| Error::Asset { path: path.to_path_buf(), problem };
    let container = gltf_data::split_container(bytes).map_err(asset)?;
    let mut warnings = Vec::new();
    let root = parse_json(container.json, &mut warnings).map_err(asset)?;
    let buffers = gltf_data::load_buffers(&root, path, container.bin).map_err(asset)?;
    let mut loader = Loader {
        path: path.to_path_buf(),
        root: &root,
        buffers: &buffers,
        warnings,
        textures: Vec::new(),
        texture_slots: HashMap::new(),
        quantized: root.extensions_used.iter().any(|e| e == "KHR_mesh_quantization"),
    };
    loader.model()
}

/// JSON text to a validated glTF document.
fn parse_json(text: &[u8], warnings: &mut Vec<String>) -> std::result::Result<json::Root, Problem> {
    // Tolerated although the spec forbids them: a UTF-8 byte order mark, and a GLB JSON chunk
    // padded with NULs instead of spaces.
    let text = text.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(text);
    let end = text.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
    let text = text.get(..end).unwrap_or(text);
    let mut value: serde_json::Value = serde_json::from_slice(text)
        .map_err(|e| format!("not a glTF file: neither GLB (no 'glTF' magic) nor valid JSON ({e})"))?;
    if !value.is_object() {
        return Err("not a glTF file: the JSON is not an object".into());
    }
    strip_custom_attributes(&mut value, warnings);
    accept_required_extensions(&mut value)?;
    fill_missing_position_bounds(&mut value, warnings);
    drop_invalid_optional_enums(&mut value, warnings);
    // Re-serialised rather than `from_value`: gltf-json keeps some extension data as raw JSON,
    // which only deserialises from text.
    let text = serde_json::to_vec(&value).map_err(|e| format!("JSON: {e}"))?;
    let root: json::Root = json::deserialize::from_slice(&text).map_err(|e| format!("not a glTF 2.0 document: {e}"))?;
    let major = root.asset.version.split('.').next().unwrap_or_default();
    if major != "2" {
        return Err(format!("glTF version {} is not supported (only 2.x)", root.asset.version));
    }
    // gltf-json's validation indexes `accessors[POSITION]` without a bounds check.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for index in prim.attributes.values() {
                if root.accessors.get(index.value()).is_none() {
                    return Err(format!(
                        "mesh {m} primitive {p}: attribute accessor {} does not exist ({} \
                         accessors)",
                        index.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    let document = gltf::Document::from_json(root).map_err(|e| match e {
        gltf::Error::Validation(errors) => {
            let shown: Vec<String> =
                errors.iter().take(5).map(|(path, error)| format!("{}: {error}", path.as_str())).collect();
            let more = errors.len().saturating_sub(shown.len());
            let more = if more > 0 { format!(" (and {more} more)") } else { String::new() };
            format!("invalid glTF: {}{more}", shown.join("; "))
        }
        other => format!("invalid glTF: {other}"),
    })?;
    Ok(document.into_json())
}

/// Refuses a file that requires an extension this loader does not honour, naming it, and
/// otherwise drops `extensionsRequired`: gltf-json would refuse KHR_mesh_quantization, which
/// the loader itself reads.
fn accept_required_extensions(value: &mut serde_json::Value) -> std::result::Result<(), Problem> {
    let Some(required) = value.as_object_mut().and_then(|o| o.remove("extensionsRequired")) else {
        return Ok(());
    };
    let names = required.as_array().ok_or("extensionsRequired is not an array")?;
    let unsupported: Vec<&str> = names
        .iter()
        .map(|n| n.as_str().ok_or("extensionsRequired holds a non-string"))
        .collect::<std::result::Result<Vec<_>, _>>()?
        .into_iter()
        .filter(|e| !SUPPORTED_REQUIRED_EXTENSIONS.contains(e))
        .collect();
    if unsupported.is_empty() {
        return Ok(());
    }
    Err(format!(
        "the file requires extension{} {}, which nostencil cannot read (it reads {}); re-export without {}",
        if unsupported.len() == 1 { "" } else { "s" },
        unsupported.join(", "),
        SUPPORTED_REQUIRED_EXTENSIONS.join(" and "),
        if unsupported.len() == 1 { "it" } else { "them" },
    ))
}

/// The spec requires `min` and `max` on POSITION accessors and gltf-json refuses a file without
/// them, but exporters do omit them, and this loader never reads them (bounds come from the
/// positions): placeholders are filled in, with a warning, instead of refusing the file.
fn fill_missing_position_bounds(value: &mut serde_json::Value, warnings: &mut Vec<String>) {
    let positions: Vec<u64> = value
        .get("meshes")
        .and_then(|m| m.as_array())
        .into_iter()
        .flatten()
        .filter_map(|mesh| mesh.get("primitives")?.as_array())
        .flatten()
        .filter_map(|prim| prim.get("attributes")?.get("POSITION")?.as_u64())
        .collect();
    let Some(accessors) = value.get_mut("accessors").and_then(|a| a.as_array_mut()) else { return };
    let is_vec3 = |v: Option<&serde_json::Value>| {
        v.and_then(|v| v.as_array()).is_some_and(|a| a.len() == 3 && a.iter().all(|x| x.is_number()))
    };
    let mut filled = Vec::new();
    for index in positions {
        let Some(accessor) = accessors.get_mut(index as usize).and_then(|a| a.as_object_mut()) else { continue };
        if is_vec3(accessor.get("min")) && is_vec3(accessor.get("max")) {
            continue;
        }
        accessor.insert("min".into(), serde_json::json!([0.0, 0.0, 0.0]));
        accessor.insert("max".into(), serde_json::json!([0.0, 0.0, 0.0]));
        if !filled.contains(&index) {
            filled.push(index);
        }
    }
    if !filled.is_empty() {
        let list: Vec<String> = filled.iter().map(u64::to_string).collect();
        warnings.push(format!(
            "POSITION accessor(s) {} lack the min/max the spec requires; bounds are computed from the data",
            list.join(", ")
        ));
    }
}

/// Optional enum-valued fields whose invalid values gltf-json refuses, although each has a
/// default that serves as well: (where, field, valid values). Such a value is dropped, with a
/// warning, so a sampler or a buffer-view hint cannot fail a whole file.
const OPTIONAL_ENUMS: &[(&str, &str, &[&str])] = &[
    ("samplers", "magFilter", &["9728", "9729"]),
    ("samplers", "minFilter", &["9728", "9729", "9984", "9985", "9986", "9987"]),
    ("samplers", "wrapS", &["33071", "33648", "10497"]),
    ("samplers", "wrapT", &["33071", "33648", "10497"]),
    ("bufferViews", "target", &["34962", "34963"]),
    ("materials", "alphaMode", &["\"OPAQUE\"", "\"MASK\"", "\"BLEND\""]),
    ("animations/samplers", "interpolation", &["\"LINEAR\"", "\"STEP\"", "\"CUBICSPLINE\""]),
];

fn drop_invalid_optional_enums(value: &mut serde_json::Value, warnings: &mut Vec<String>) {
    for (place, field, valid) in OPTIONAL_ENUMS {
        // "animations/samplers": the samplers of every animation.
        let mut objects: Vec<(String, &mut serde_json::Value)> = Vec::new();
        let (outer, inner) = place.split_once('/').map_or((*place, None), |(o, i)| (o, Some(i)));
        let Some(list) = value.get_mut(outer).and_then(|v| v.as_array_mut()) else { continue };
        for (i, item) in list.iter_mut().enumerate() {
            match inner {
                None => objects.push((format!("{outer}[{i}]"), item)),
                Some(inner) => {
                    if let Some(nested) = item.get_mut(inner).and_then(|v| v.as_array_mut()) {
                        for (k, object) in nested.iter_mut().enumerate() {
                            objects.push((format!("{outer}[{i}].{inner}[{k}]"), object));
                        }
                    }
                }
            }
        }
        for (path, object) in objects {
            let Some(map) = object.as_object_mut() else { continue };
            let Some(found) = map.get(*field) else { continue };
            let text = found.to_string();
            if !valid.contains(&text.as_str()) {
                map.remove(*field);
                warnings.push(format!("{path}.{field} {text} is not a valid value; the default is used"));
            }
        }
    }
}

/// Application-specific attributes (`_NAME`) are valid glTF, but gltf-json without its
/// `extras` feature rejects them; they are removed before parsing.
fn strip_custom_attributes(value: &mut serde_json::Value, warnings: &mut Vec<String>) {
    let Some(meshes) = value.get_mut("meshes").and_then(|m| m.as_array_mut()) else {
        return;
    };
    for (m, mesh) in meshes.iter_mut().enumerate() {
        let Some(prims) = mesh.get_mut("primitives").and_then(|p| p.as_array_mut()) else {
            continue;
        };
        for (p, prim) in prims.iter_mut().enumerate() {
            let Some(attrs) = prim.get_mut("attributes").and_then(|a| a.as_object_mut()) else {
                continue;
            };
            let custom: Vec<String> = attrs.keys().filter(|k| k.starts_with('_')).cloned().collect();
            for key in custom {
                attrs.remove(&key);
                warnings.push(format!("mesh {m} primitive {p}: custom attribute {key} ignored"));
            }
        }
    }
}

/// JOINTS_0 and WEIGHTS_0 of one primitive.
type SkinAttributes = (Vec<[u16; 4]>, Vec<[f32; 4]>);

struct Loader<'a> {
    path: PathBuf,
    root: &'a json::Root,
    buffers: &'a [Vec<u8>],
    warnings: Vec<String>,
    textures: Vec<TextureRgba8>,
    /// glTF texture index -> index in `textures` (None: could not be decoded, warned).
    texture_slots: HashMap<usize, Option<usize>>,
    /// KHR_mesh_quantization is used: positions and UVs may be (un)normalised integers,
    /// dequantised by the node transforms.
    quantized: bool,
}

fn checked<V: Copy>(c: &Checked<V>) -> Option<V> {
    match c {
        Checked::Valid(v) => Some(*v),
        Checked::Invalid => None,
    }
}

/// "mesh 3 'Cylinder'" or "mesh 3".
fn label(kind: &str, index: usize, name: Option<&str>) -> String {
    match name {
        Some(name) => format!("{kind} {index} '{name}'"),
        None => format!("{kind} {index}"),
    }
}

impl Loader<'_> {
    fn fail(&self, problem: impl Into<String>) -> Error {
        Error::Asset { path: self.path.clone(), problem: problem.into() }
    }

    fn accessor(&self, index: usize, what: &str, types: &[T], components: &[C]) -> Result<Dense> {
        gltf_data::read_accessor(self.root, self.buffers, index, types, components)
            .map_err(|e| self.fail(format!("{what}: {e}")))
    }

    /// A position or texture coordinate: float, or under KHR_mesh_quantization any 8- or 16-bit
    /// integer, normalised or not.
    fn quantizable_floats(&self, index: usize, what: &str, ty: T, plain: &[C]) -> Result<Vec<f32>> {
        if !self.quantized {
            return self.floats(index, what, ty, plain);
        }
        Ok(self.accessor(index, what, &[ty], &[C::F32, C::I8, C::U8, C::I16, C::U16])?.floats())
    }

    /// A float attribute; integer storage must be normalised.
    fn floats(&self, index: usize, what: &str, ty: T, components: &[C]) -> Result<Vec<f32>> {
        let dense = self.accessor(index, what, &[ty], components)?;
        if dense.component != C::F32 && !dense.normalized {
            return Err(self.fail(format!(
                "{what}: accessor {index} stores {} without `normalized: true`",
                gltf_data::component_name(dense.component)
            )));
        }
        Ok(dense.floats())
    }

    fn model(&mut self) -> Result<Model> {
        let nodes = self.nodes()?;
        let roots = self.roots(&nodes);
        let materials = self.materials()?;
        let mut meshes = self.meshes(materials.len())?;
        let skins = self.skins()?;
        self.check_skinned_meshes(&nodes, &skins, &mut meshes)?;
        let animations = self.animations()?;
        let cameras = self.cameras()?;
        let lights = self.lights();
        for ext in &self.root.extensions_used {
            if !SUPPORTED_REQUIRED_EXTENSIONS.contains(&ext.as_str()) {
                self.warnings.push(format!("extension {ext} is not supported and was ignored"));
            }
        }
        Ok(Model {
            meshes,
            materials,
            textures: std::mem::take(&mut self.textures),
            nodes,
            roots,
            skins,
            animations,
            cameras,
            lights,
            warnings: std::mem::take(&mut self.warnings),
        })
    }

    fn nodes(&mut self) -> Result<Vec<Node>> {
        let count = self.root.nodes.len();
        let mut nodes = Vec::with_capacity(count);
        for (i, n) in self.root.nodes.iter().enumerate() {
            let what = label("node", i, n.name.as_deref());
            let local = self.node_transform(&what, n)?;
            let light = n.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()).map(|l| l.light.value());
            let light_count = self.light_count();
            if let Some(l) = light.filter(|&l| l >= light_count) {
                return Err(self.fail(format!("{what}: light {l} does not exist")));
            }
            nodes.push(Node {
                name: n.name.clone(),
                parent: None,
                children: Vec::new(),
                local,
                mesh: n.mesh.map(|m| m.value()),
                skin: n.skin.map(|s| s.value()),
                camera: n.camera.map(|c| c.value()),
                light,
            });
        }
        // Children and parents; the hierarchy must be a forest.
        for i in 0..count {
            let children: Vec<usize> = self
                .root
                .nodes
                .get(i)
                .and_then(|n| n.children.as_ref())
                .map(|c| c.iter().map(|c| c.value()).collect())
                .unwrap_or_default();
            for &c in &children {
                if c == i {
                    return Err(self.fail(format!("node {i} lists itself as a child")));
                }
                let child = nodes.get_mut(c).ok_or_else(|| self.fail(format!("node {i}: child {c} does not exist")))?;
                if let Some(p) = child.parent {
                    return Err(self.fail(format!("node {c} is a child of both node {p} and node {i}")));
                }
                child.parent = Some(i);
            }
            if let Some(node) = nodes.get_mut(i) {
                node.children = children;
            }
        }
        for start in 0..count {
            let mut at = start;
            for _ in 0..=count {
                match nodes.get(at).and_then(|n| n.parent) {
                    Some(p) if p == start => {
                        return Err(self.fail(format!("the node hierarchy has a cycle through node {start}")))
                    }
                    Some(p) => at = p,
                    None => break,
                }
            }
        }
        Ok(nodes)
    }

    fn node_transform(&mut self, what: &str, n: &json::Node) -> Result<Transform> {
        if let Some(m) = n.matrix {
            if m.iter().any(|x| !x.is_finite()) {
                return Err(self.fail(format!("{what}: matrix has a non-finite element")));
            }
            let matrix = Mat4::from_cols_array(&m);
            let det = matrix.determinant();
            let t = if det.abs() > 1e-30 {
                Transform::from_mat4(matrix)
            } else {
                // Singular (a zero scale): keep the axis lengths, drop the rotation.
                Transform {
                    translation: matrix.w_axis.truncate(),
                    rotation: Quat::IDENTITY,
                    scale: Vec3::new(
                        matrix.x_axis.truncate().length(),
                        matrix.y_axis.truncate().length(),
                        matrix.z_axis.truncate().length(),
                    ),
                }
            };
            let error = (t.to_mat4() - matrix).abs().to_cols_array();
            let scale = m.iter().fold(1.0f32, |a, x| a.max(x.abs()));
            if !t.to_mat4().is_finite() || error.iter().any(|e| *e > 1e-4 * scale) {
                self.warnings.push(format!(
                    "{what}: matrix has shear or a projective part; its translation / rotation \
                     / scale approximation is used"
                ));
            }
            return Ok(t);
        }
        let translation = Vec3::from_array(n.translation.unwrap_or([0.0; 3]));
        let scale = Vec3::from_array(n.scale.unwrap_or([1.0; 3]));
        let r = n.rotation.as_ref().map_or([0.0, 0.0, 0.0, 1.0], |r| r.0);
        let rotation = Quat::from_array(r);
        if !translation.is_finite() || !scale.is_finite() || !rotation.is_finite() {
            return Err(self.fail(format!("{what}: non-finite translation, rotation or scale")));
        }
        let len = rotation.length();
        if len < 1e-6 {
            return Err(self.fail(format!("{what}: rotation is a zero quaternion")));
        }
        Ok(Transform { translation, rotation: rotation / len, scale })
    }

    fn light_count(&self) -> usize {
        self.root.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()).map_or(0, |l| l.lights.len())
    }

    fn roots(&mut self, nodes: &[Node]) -> Vec<usize> {
        let scene = self.root.scene.map(|s| s.value()).or(if self.root.scenes.is_empty() { None } else { Some(0) });
        let Some(scene) = scene.and_then(|s| self.root.scenes.get(s)) else {
            return (0..nodes.len()).filter(|&i| nodes.get(i).is_some_and(|n| n.parent.is_none())).collect();
        };
        let mut roots = Vec::new();
        for index in scene.nodes.iter().map(|n| n.value()) {
            match nodes.get(index).map(|n| n.parent) {
                Some(None) => roots.push(index),
                Some(Some(p)) => {
                    self.warnings.push(format!("scene lists node {index}, which is a child of node {p}; skipped"))
                }
                None => self.warnings.push(format!("scene lists node {index}, which does not exist")),
            }
        }
        roots
    }

    fn materials(&mut self) -> Result<Vec<Material>> {
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
                Some(info) => self
                    .texture(info.index.value(), &what)?
                    .map(|texture| TextureRef { texture, tex_coord: info.tex_coord }),
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
                alpha_mode,
                double_sided: m.double_sided,
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
            (_, Some(view)) => gltf_data::view_bytes(self.root, self.buffers, view.value())
                .map_err(|e| self.fail(format!("{what}: {e}")))?
                .to_vec(),
            (Some(uri), None) => match gltf_data::decode_data_uri(uri) {
                Some(decoded) => decoded.map_err(|e| self.fail(format!("{what}: {e}")))?,
                None => gltf_data::read_external(&self.path, uri).map_err(|e| self.fail(format!("{what}: {e}")))?,
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

    fn meshes(&mut self, material_count: usize) -> Result<Vec<Mesh>> {
        let mut out = Vec::with_capacity(self.root.meshes.len());
        for (m, mesh) in self.root.meshes.iter().enumerate() {
            let mesh_label = label("mesh", m, mesh.name.as_deref());
            let mut primitives = Vec::with_capacity(mesh.primitives.len());
            for (p, prim) in mesh.primitives.iter().enumerate() {
                let what = format!("{mesh_label} primitive {p}");
                if let Some(primitive) = self.primitive(&what, prim, material_count)? {
                    primitives.push(primitive);
                }
            }
            out.push(Mesh { name: mesh.name.clone(), primitives });
        }
        Ok(out)
    }

    fn primitive(
        &mut self,
        what: &str,
        prim: &json::mesh::Primitive,
        material_count: usize,
    ) -> Result<Option<Primitive>> {
        use json::mesh::{Mode, Semantic};
        let mode = checked(&prim.mode).unwrap_or(Mode::Triangles);
        if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            self.warnings.push(format!("{what}: {mode:?} primitive skipped (only triangles are drawn)"));
            return Ok(None);
        }
        let attribute = |s: Semantic| prim.attributes.get(&Checked::Valid(s)).map(|i| i.value());
        let Some(pos_index) = attribute(Semantic::Positions) else {
            self.warnings.push(format!("{what}: no POSITION attribute; skipped"));
            return Ok(None);
        };
        if prim.targets.as_ref().is_some_and(|t| !t.is_empty()) {
            self.warnings.push(format!("{what}: morph targets are not supported and were ignored"));
        }

        let flat = self.quantizable_floats(pos_index, &format!("{what} POSITION"), T::Vec3, &[C::F32])?;
        let positions: Vec<Vec3> = flat.chunks_exact(3).map(Vec3::from_slice).collect();
        if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
            return Err(self.fail(format!(
                "{what}: POSITION of vertex {v} is not finite ({})",
                positions.get(v).copied().unwrap_or_default()
            )));
        }
        let n = positions.len();
        let same_count = |this: &Self, name: &str, count: usize| -> Result<()> {
            if count == n {
                Ok(())
            } else {
                Err(this.fail(format!("{what}: {name} has {count} elements but POSITION has {n}")))
            }
        };

        let normals = match attribute(Semantic::Normals) {
            Some(i) => {
                let name = format!("{what} NORMAL");
                let components: &[C] = if self.quantized { FLOAT_OR_SNORM } else { &[C::F32] };
                let flat = self.floats(i, &name, T::Vec3, components)?;
                let normals: Vec<Vec3> = flat.chunks_exact(3).map(Vec3::from_slice).collect();
                same_count(self, "NORMAL", normals.len())?;
                if let Some(v) = normals.iter().position(|p| !p.is_finite()) {
                    return Err(self.fail(format!("{name} of vertex {v} is not finite")));
                }
                Some(normals.into_iter().map(|v| v.try_normalize().unwrap_or(Vec3::Z)).collect::<Vec<_>>())
            }
            None => None,
        };

        let uv = |set: u32| -> Result<Option<Vec<Vec2>>> {
            let Some(i) = attribute(Semantic::TexCoords(set)) else {
                return Ok(None);
            };
            let name = format!("TEXCOORD_{set}");
            let flat = self.quantizable_floats(i, &format!("{what} {name}"), T::Vec2, FLOAT_OR_UNORM)?;
            let uvs: Vec<Vec2> = flat.chunks_exact(2).map(Vec2::from_slice).collect();
            same_count(self, &name, uvs.len())?;
            Ok(Some(uvs))
        };
        let uv0 = uv(0)?;
        let uv1 = uv(1)?;

        let colors = match attribute(Semantic::Colors(0)) {
            Some(i) => {
                let name = format!("{what} COLOR_0");
                let dense = self.accessor(i, &name, &[T::Vec3, T::Vec4], FLOAT_OR_UNORM)?;
                if dense.component != C::F32 && !dense.normalized {
                    return Err(self.fail(format!("{name}: integer colours must be normalized")));
                }
                let k = dense.components();
                let flat = dense.floats();
                let colors: Vec<Vec4> = flat
                    .chunks_exact(k)
                    .map(|c| match c {
                        [r, g, b] => Vec4::new(*r, *g, *b, 1.0),
                        _ => Vec4::from_slice(c),
                    })
                    .collect();
                same_count(self, "COLOR_0", colors.len())?;
                Some(colors)
            }
            None => None,
        };

        let (joints, weights) = match (attribute(Semantic::Joints(0)), attribute(Semantic::Weights(0))) {
            (Some(j), Some(w)) => {
                // Further sets (JOINTS_1/WEIGHTS_1, ...) carry influences 5 to 8 and beyond.
                let mut sets = vec![(j, w)];
                while let (Some(j), Some(w)) =
                    (attribute(Semantic::Joints(sets.len() as u32)), attribute(Semantic::Weights(sets.len() as u32)))
                {
                    sets.push((j, w));
                }
                let (joints, weights) = self.skin_attributes(what, &sets, n)?;
                (Some(joints), Some(weights))
            }
            (None, None) => (None, None),
            _ => {
                self.warnings.push(format!("{what}: JOINTS_0 without WEIGHTS_0 or the reverse; drawn unskinned"));
                (None, None)
            }
        };

        let (indices, source_index_width) = match prim.indices {
            Some(i) => {
                let name = format!("{what} indices");
                let dense = self.accessor(i.value(), &name, &[T::Scalar], &[C::U8, C::U16, C::U32])?;
                let width = match dense.component {
                    C::U8 => 1,
                    C::U16 => 2,
                    _ => 4,
                };
                let indices = dense.uints();
                if let Some((k, bad)) = indices.iter().enumerate().find(|(_, &x)| x as usize >= n) {
                    return Err(self.fail(format!("{name}: index {k} is {bad}, out of range of the {n} vertices")));
                }
                (indices, Some(width))
            }
            None => {
                let n32 =
                    u32::try_from(n).map_err(|_| self.fail(format!("{what}: {n} vertices do not fit u32 indices")))?;
                ((0..n32).collect(), None)
            }
        };
        let indices = match mode {
            Mode::TriangleStrip => strip_to_list(&indices),
            Mode::TriangleFan => fan_to_list(&indices),
            _ => {
                if indices.len() % 3 != 0 {
                    return Err(
                        self.fail(format!("{what}: {} indices is not a whole number of triangles", indices.len()))
                    );
                }
                indices
            }
        };

        let material = prim.material.map(|m| m.value());
        if let Some(m) = material.filter(|&m| m >= material_count) {
            return Err(self.fail(format!("{what}: material {m} does not exist")));
        }

        let (normals, normals_generated) = match normals {
            Some(normals) => (normals, false),
            None => (smooth_normals(&positions, &indices), true),
        };
        Ok(Some(Primitive {
            positions,
            normals,
            normals_generated,
            uv0,
            uv1,
            colors,
            joints,
            weights,
            indices,
            source_index_width,
            material,
        }))
    }

    /// One JOINTS_k/WEIGHTS_k pair: `n` vertices of four (joint, weight) influences.
    fn influence_set(
        &self,
        what: &str,
        set: usize,
        (joints, weights): (usize, usize),
        n: usize,
    ) -> Result<SkinAttributes> {
        let name = format!("{what} JOINTS_{set}");
        let raw = self.accessor(joints, &name, &[T::Vec4], &[C::U8, C::U16])?.uints();
        let joints: Vec<[u16; 4]> =
            raw.chunks_exact(4).map(|j| [j[0] as u16, j[1] as u16, j[2] as u16, j[3] as u16]).collect();
        if joints.len() != n {
            return Err(self.fail(format!("{name} has {} elements but POSITION has {n}", joints.len())));
        }
        let name = format!("{what} WEIGHTS_{set}");
        let flat = self.floats(weights, &name, T::Vec4, FLOAT_OR_UNORM)?;
        let weights: Vec<[f32; 4]> = flat.chunks_exact(4).map(|w| [w[0], w[1], w[2], w[3]]).collect();
        if weights.len() != n {
            return Err(self.fail(format!("{name} has {} elements but POSITION has {n}", weights.len())));
        }
        if let Some((v, w)) = weights.iter().enumerate().find(|(_, w)| w.iter().any(|x| !x.is_finite() || *x < -1e-6)) {
            return Err(
                self.fail(format!("{name}: vertex {v} has weights {w:?}; weights must be finite and not negative"))
            );
        }
        Ok((joints, weights))
    }

    /// Four influences per vertex, as the GPU skins them: with more sets than one, the four
    /// strongest of all; then weights renormalised to sum to 1 (exporters round them, or drop
    /// the influences past four without renormalising).
    fn skin_attributes(&mut self, what: &str, sets: &[(usize, usize)], n: usize) -> Result<SkinAttributes> {
        let mut read = Vec::with_capacity(sets.len());
        for (set, pair) in sets.iter().enumerate() {
            read.push(self.influence_set(what, set, *pair, n)?);
        }
        let mut joints = Vec::with_capacity(n);
        let mut weights = Vec::with_capacity(n);
        let mut dropped = 0usize;
        let mut all = Vec::with_capacity(4 * sets.len());
        for v in 0..n {
            all.clear();
            for (j, w) in &read {
                all.extend(j[v].iter().zip(&w[v]).map(|(j, w)| (*j, w.max(0.0))));
            }
            if all.len() > 4 {
                // Stable: equal weights keep the file's order.
                all.sort_by(|a, b| b.1.total_cmp(&a.1));
                dropped += all[4..].iter().any(|(_, w)| *w > 0.0) as usize;
            }
            joints.push([0, 1, 2, 3].map(|k| all[k].0));
            weights.push([0, 1, 2, 3].map(|k| all[k].1));
        }
        let name = format!("{what} WEIGHTS_0");
        if dropped > 0 {
            self.warnings.push(format!(
                "{name}..{}: {dropped} vertices have more than 4 influences; the 4 strongest are kept",
                sets.len() - 1
            ));
        }
        let mut unweighted = 0usize;
        let mut renormalised = 0usize;
        for w in weights.iter_mut() {
            let sum: f32 = w.iter().sum();
            if sum <= 0.0 {
                *w = [1.0, 0.0, 0.0, 0.0];
                unweighted += 1;
            } else {
                if (sum - 1.0).abs() > 1e-3 {
                    renormalised += 1;
                }
                for x in w.iter_mut() {
                    *x /= sum;
                }
            }
        }
        if unweighted > 0 {
            self.warnings
                .push(format!("{name}: {unweighted} vertices have all-zero weights; bound to their first joint"));
        }
        if renormalised > 0 {
            self.warnings.push(format!("{name}: {renormalised} vertices had weights not summing to 1; renormalised"));
        }
        Ok((joints, weights))
    }

    fn skins(&mut self) -> Result<Vec<Skin>> {
        let mut out = Vec::with_capacity(self.root.skins.len());
        for (s, skin) in self.root.skins.iter().enumerate() {
            let what = label("skin", s, skin.name.as_deref());
            let joints: Vec<usize> = skin.joints.iter().map(|j| j.value()).collect();
            if joints.is_empty() {
                return Err(self.fail(format!("{what} has no joints")));
            }
            if joints.len() > MAX_JOINTS {
                return Err(self.fail(format!(
                    "{what} has {} joints; at most {MAX_JOINTS} are supported (the joint \
                     matrices live in a {} KiB uniform buffer)",
                    joints.len(),
                    MAX_JOINTS * 64 / 1024
                )));
            }
            if let Some(j) = joints.iter().find(|&&j| j >= self.root.nodes.len()) {
                return Err(self.fail(format!("{what}: joint node {j} does not exist")));
            }
            let inverse_bind = match skin.inverse_bind_matrices {
                Some(i) => {
                    let name = format!("{what} inverseBindMatrices");
                    let flat = self.floats(i.value(), &name, T::Mat4, &[C::F32])?;
                    let matrices: Vec<Mat4> = flat.chunks_exact(16).map(Mat4::from_cols_slice).collect();
                    if matrices.len() < joints.len() {
                        return Err(self.fail(format!(
                            "{name} has {} matrices for {} joints",
                            matrices.len(),
                            joints.len()
                        )));
                    }
                    if let Some(k) = matrices.iter().position(|m| !m.is_finite()) {
                        return Err(self.fail(format!("{name}: matrix {k} is not finite")));
                    }
                    matrices.into_iter().take(joints.len()).collect()
                }
                None => vec![Mat4::IDENTITY; joints.len()],
            };
            let skeleton = skin.skeleton.map(|s| s.value());
            if let Some(k) = skeleton.filter(|&k| k >= self.root.nodes.len()) {
                return Err(self.fail(format!("{what}: skeleton node {k} does not exist")));
            }
            out.push(Skin { name: skin.name.clone(), joints, inverse_bind, skeleton });
        }
        Ok(out)
    }

    /// Joint indices of every mesh drawn with a skin must stay inside that skin.
    fn check_skinned_meshes(&mut self, nodes: &[Node], skins: &[Skin], meshes: &mut [Mesh]) -> Result<()> {
        for (i, node) in nodes.iter().enumerate() {
            let Some(s) = node.skin else { continue };
            let skin = skins.get(s).ok_or_else(|| self.fail(format!("node {i}: skin {s} does not exist")))?;
            let Some(m) = node.mesh else {
                self.warnings.push(format!("node {i} has skin {s} but no mesh; skin unused"));
                continue;
            };
            let mesh = meshes.get_mut(m).ok_or_else(|| self.fail(format!("node {i}: mesh {m} does not exist")))?;
            let mesh_label = label("mesh", m, mesh.name.as_deref());
            let joint_count = skin.joints.len();
            for (p, prim) in mesh.primitives.iter_mut().enumerate() {
                let (Some(joints), Some(weights)) = (&mut prim.joints, &prim.weights) else {
                    self.warnings.push(format!(
                        "node {i} uses skin {s}, but {mesh_label} primitive {p} has no \
                         JOINTS_0/WEIGHTS_0; drawn rigid"
                    ));
                    continue;
                };
                let mut zeroed = 0usize;
                for (v, (j, w)) in joints.iter_mut().zip(weights).enumerate() {
                    for (slot, (joint, weight)) in j.iter_mut().zip(w).enumerate() {
                        if (*joint as usize) < joint_count {
                            continue;
                        }
                        if *weight > 0.0 {
                            return Err(Error::Asset {
                                path: self.path.clone(),
                                problem: format!(
                                    "{mesh_label} primitive {p} JOINTS_0: vertex {v} slot \
                                     {slot} uses joint {joint} with weight {weight}, but skin \
                                     {s} (used by node {i}) has {joint_count} joints"
                                ),
                            });
                        }
                        *joint = 0;
                        zeroed += 1;
                    }
                }
                if zeroed > 0 {
                    self.warnings.push(format!(
                        "{mesh_label} primitive {p}: {zeroed} zero-weight joint slots pointed \
                         outside skin {s}; set to joint 0"
                    ));
                }
            }
        }
        Ok(())
    }

    fn animations(&mut self) -> Result<Vec<Animation>> {
        let mut out = Vec::with_capacity(self.root.animations.len());
        for (a, anim) in self.root.animations.iter().enumerate() {
            let what = label("animation", a, anim.name.as_deref());
            let mut channels = Vec::with_capacity(anim.channels.len());
            let mut skipped_weights = 0;
            for (c, channel) in anim.channels.iter().enumerate() {
                let node = channel.target.node.value();
                let property = match checked(&channel.target.path) {
                    Some(json::animation::Property::Translation) => Property::Translation,
                    Some(json::animation::Property::Rotation) => Property::Rotation,
                    Some(json::animation::Property::Scale) => Property::Scale,
                    Some(json::animation::Property::MorphTargetWeights) => {
                        skipped_weights += 1;
                        continue;
                    }
                    None => return Err(self.fail(format!("{what} channel {c}: bad target path"))),
                };
                let here = format!("{what} channel {c} (node {node} {property:?})");
                if node >= self.root.nodes.len() {
                    return Err(self.fail(format!("{here}: node {node} does not exist")));
                }
                let s = channel.sampler.value();
                let sampler =
                    anim.samplers.get(s).ok_or_else(|| self.fail(format!("{here}: sampler {s} does not exist")))?;
                let interpolation = match checked(&sampler.interpolation) {
                    Some(json::animation::Interpolation::Step) => Interpolation::Step,
                    Some(json::animation::Interpolation::CubicSpline) => Interpolation::CubicSpline,
                    _ => Interpolation::Linear,
                };
                let times = self.floats(sampler.input.value(), &format!("{here} input"), T::Scalar, &[C::F32])?;
                let output = format!("{here} output");
                let values = match property {
                    Property::Rotation => {
                        let flat = self.floats(sampler.output.value(), &output, T::Vec4, FLOAT_OR_NORM)?;
                        ChannelValues::Rotation(flat.chunks_exact(4).map(Quat::from_slice).collect())
                    }
                    _ => {
                        let flat = self.floats(sampler.output.value(), &output, T::Vec3, &[C::F32])?;
                        ChannelValues::Vec3(flat.chunks_exact(3).map(Vec3::from_slice).collect())
                    }
                };
                let channel = Channel::new(node, property, interpolation, times, values)
                    .map_err(|e| self.fail(format!("{here} sampler {s}: {e}")))?;
                channels.push(channel);
            }
            if skipped_weights > 0 {
                self.warnings.push(format!("{what}: {skipped_weights} morph-target weight channels skipped"));
            }
            let duration = channels.iter().map(Channel::end_time).fold(0.0, f32::max);
            out.push(Animation { name: anim.name.clone(), channels, duration });
        }
        Ok(out)
    }

    fn cameras(&mut self) -> Result<Vec<Camera>> {
        use json::camera::Type as CameraType;
        let mut out = Vec::with_capacity(self.root.cameras.len());
        for (i, cam) in self.root.cameras.iter().enumerate() {
            let what = label("camera", i, cam.name.as_deref());
            let projection = match (checked(&cam.type_), &cam.perspective, &cam.orthographic) {
                (Some(CameraType::Perspective), Some(p), _) => {
                    Projection::Perspective { yfov: p.yfov, aspect_ratio: p.aspect_ratio, znear: p.znear, zfar: p.zfar }
                }
                (Some(CameraType::Orthographic), _, Some(o)) => {
                    Projection::Orthographic { xmag: o.xmag, ymag: o.ymag, znear: o.znear, zfar: o.zfar }
                }
                _ => return Err(self.fail(format!("{what}: type does not match its perspective/orthographic block"))),
            };
            out.push(Camera { name: cam.name.clone(), projection });
        }
        Ok(out)
    }

    fn lights(&self) -> Vec<Light> {
        use json::extensions::scene::khr_lights_punctual::Type as LightType;
        let Some(ext) = self.root.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()) else {
            return Vec::new();
        };
        ext.lights
            .iter()
            .map(|l| Light {
                name: l.name.clone(),
                kind: match (checked(&l.type_), &l.spot) {
                    (Some(LightType::Spot), Some(spot)) => LightKind::Spot {
                        inner_cone_angle: spot.inner_cone_angle,
                        outer_cone_angle: spot.outer_cone_angle,
                    },
                    (Some(LightType::Directional), _) => LightKind::Directional,
                    _ => LightKind::Point,
                },
                color: Vec3::from_array(l.color),
                intensity: l.intensity,
                range: l.range,
            })
            .collect()
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

/// glTF 2.0 section 3.7.2.1: strip triangle i is (v_i, v_{i+1+i%2}, v_{i+2-i%2}), which keeps
/// every triangle's winding the same as the first.
fn strip_to_list(strip: &[u32]) -> Vec<u32> {
    let mut out = Vec::with_capacity(strip.len().saturating_sub(2) * 3);
    for (i, w) in strip.windows(3).enumerate() {
        if let [a, b, c] = *w {
            if i % 2 == 0 {
                out.extend_from_slice(&[a, b, c]);
            } else {
                out.extend_from_slice(&[a, c, b]);
            }
        }
    }
    out
}

/// Fan triangle i is (v_{i+1}, v_{i+2}, v_0).
fn fan_to_list(fan: &[u32]) -> Vec<u32> {
    let Some((&first, rest)) = fan.split_first() else {
        return Vec::new();
    };
    let mut out = Vec::with_capacity(rest.len().saturating_sub(1) * 3);
    for w in rest.windows(2) {
        if let [b, c] = *w {
            out.extend_from_slice(&[b, c, first]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_become_lists_with_consistent_winding() {
        assert_eq!(strip_to_list(&[0, 1, 2, 3, 4]), [0, 1, 2, 1, 3, 2, 2, 3, 4]);
        assert_eq!(fan_to_list(&[0, 1, 2, 3]), [1, 2, 0, 2, 3, 0]);
        assert!(strip_to_list(&[0, 1]).is_empty());
        assert!(fan_to_list(&[]).is_empty());
    }
}
