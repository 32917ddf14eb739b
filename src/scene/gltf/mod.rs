//! glTF 2.0 (`.gltf` with external or data-URI buffers, and `.glb`) into a `Model`.
//!
//! The gltf crate parses and validates the JSON (references, enums, required fields) after
//! `repair` has fixed what it would needlessly refuse (see `document::tolerated` for the valid
//! forms its validation would refuse); the bytes are read by `glb`, `buffers`
//! and `accessors` with checked offsets. On top of that the loader checks what the
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
//! - Only base-colour and emissive textures are decoded (sRGB), and only PNG or JPEG; a texture
//!   in another format or without `source` is dropped with a warning and the material keeps its
//!   factor. KHR_texture_transform, KHR_materials_unlit and the diffuse of
//!   KHR_materials_pbrSpecularGlossiness are read; transmission and variants are accepted with a
//!   warning (not rendered; the default material is used).
//! - Buffers are read on first use: one nothing drawn needs is never loaded (a bad URI there is
//!   no error). EXT_meshopt_compression views are decoded with meshoptimizer. Draco is not
//!   decoded: a Draco primitive is drawn from its uncompressed fallback, or refused by name.
//! - Accessors without a bufferView are zeros, within a budget per file of 1 MiB plus 4 bytes
//!   per byte of the file (at most `MAX_ZERO_FILLED_BYTES`); counts are checked against the
//!   bytes present before anything is allocated.

mod accessors;
mod animation;
mod buffers;
mod cameras_and_lights;
mod document;
#[cfg(test)]
mod extension_tests;
mod glb;
mod materials;
mod meshes;
mod meshopt;
mod nodes;
mod repair;
mod skins;
#[cfg(test)]
mod tests;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use gltf::json;
use json::accessor::{ComponentType as C, Type as T};
use json::validation::Checked;

use crate::error::{Error, Result};
use crate::scene::model::{Model, TextureRgba8};
use accessors::Dense;

/// What went wrong, without the file name: `load_gltf_slice` wraps it in `Error::Asset`.
type Problem = String;

/// Component types glTF allows for float attributes stored as normalised integers.
const FLOAT_OR_UNORM: &[C] = &[C::F32, C::U8, C::U16];
const FLOAT_OR_NORM: &[C] = &[C::F32, C::I8, C::U8, C::I16, C::U16];
/// Normals under KHR_mesh_quantization: float or normalised signed integers.
const FLOAT_OR_SNORM: &[C] = &[C::F32, C::I8, C::I16];

/// Loads a `.gltf` or `.glb` file. External buffers and images are resolved relative to it.
pub fn load_gltf(path: &Path) -> Result<Model> {
    let bytes = std::fs::read(path)
        .map_err(|e| Error::Asset { path: path.to_path_buf(), problem: format!("cannot read the file: {e}") })?;
    load_gltf_slice(&bytes, path)
}

/// Loads glTF from memory; `path` names the file in errors and anchors relative URIs.
pub fn load_gltf_slice(bytes: &[u8], path: &Path) -> Result<Model> {
    let asset = |problem: Problem| Error::Asset { path: path.to_path_buf(), problem };
    let container = glb::split_container(bytes).map_err(asset)?;
    let mut warnings = Vec::new();
    let root = document::parse_json(container.json, &mut warnings).map_err(asset)?;
    let buffers = buffers::Buffers::new(&root, path, container.bin, bytes.len());
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

struct Loader<'a> {
    path: PathBuf,
    root: &'a json::Root,
    buffers: &'a buffers::Buffers<'a>,
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

/// Extensions the loader reads, or that change nothing it draws, beyond those it honours when
/// required (`repair::SUPPORTED_REQUIRED_EXTENSIONS`).
const READ_EXTENSIONS: &[&str] = &[
    // A texture with only such a source is named in a warning of its own.
    "EXT_texture_webp",
    "KHR_texture_basisu",
    "MSFT_texture_dds",
];

impl Loader<'_> {
    /// One warning per extension the file uses that nothing here reads (each named once), and
    /// the one KHR_materials_variants warning.
    fn extension_warnings(&mut self) {
        let mut ignored: Vec<&str> = Vec::new();
        for ext in &self.root.extensions_used {
            let ext = ext.as_str();
            let read = repair::SUPPORTED_REQUIRED_EXTENSIONS.contains(&ext) || READ_EXTENSIONS.contains(&ext);
            if !read && !ignored.contains(&ext) {
                ignored.push(ext);
            }
        }
        if !ignored.is_empty() {
            self.warnings.push(format!("extensions not supported and ignored: {}", ignored.join(", ")));
        }
        if self.root.extensions_used.iter().any(|e| e == "KHR_materials_variants") {
            self.warnings.push(
                "KHR_materials_variants: each primitive is drawn with its default material; variants are not \
                 selectable"
                    .into(),
            );
        }
    }

    fn fail(&self, problem: impl Into<String>) -> Error {
        Error::Asset { path: self.path.clone(), problem: problem.into() }
    }

    fn accessor(&self, index: usize, what: &str, types: &[T], components: &[C]) -> Result<Dense> {
        accessors::read_accessor(self.root, self.buffers, index, types, components)
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
                accessors::component_name(dense.component)
            )));
        }
        Ok(dense.floats())
    }

    fn model(&mut self) -> Result<Model> {
        let mut nodes = self.nodes()?;
        let mut roots = self.roots(&nodes);
        let materials = self.materials()?;
        let mut meshes = self.meshes(&materials)?;
        if nodes.is_empty() && !meshes.is_empty() {
            (nodes, roots) = self.nodes_for_unplaced_meshes(meshes.len());
        }
        let skins = self.skins()?;
        self.check_skinned_meshes(&nodes, &skins, &mut meshes)?;
        let animations = self.animations()?;
        let cameras = self.cameras()?;
        let lights = self.lights();
        self.extension_warnings();
        self.warnings.extend(self.buffers.take_warnings());
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
}
