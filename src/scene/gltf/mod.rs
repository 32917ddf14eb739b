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
mod loader;
mod materials;
mod meshes;
mod meshopt;
mod nodes;
mod problem;
mod repair;
mod skins;
#[cfg(test)]
pub(crate) mod tests;

use std::collections::HashMap;
use std::path::Path;

use crate::error::{Error, Result};
use crate::scene::model::Model;
use loader::Loader;
use problem::Problem;

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
