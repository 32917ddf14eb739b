//! The loader's state over one document, the helpers its parts share (`checked`, `label`, the
//! component types a float attribute may have), and the walk that builds the `Model`; each part
//! of the document (`nodes`, `materials`, `meshes`, `skins`, `animation`, `cameras_and_lights`)
//! adds its own methods in its own file.

use std::collections::HashMap;
use std::path::PathBuf;

use gltf::json;
use json::accessor::{ComponentType as C, Type as T};
use json::validation::Checked;

use super::accessors::{self, Dense};
use super::buffers::Buffers;
use super::repair;
use crate::error::{Error, Result};
use crate::scene::model::{Model, TextureRgba8};

/// Component types glTF allows for float attributes stored as normalised integers.
pub(super) const FLOAT_OR_UNORM: &[C] = &[C::F32, C::U8, C::U16];
pub(super) const FLOAT_OR_NORM: &[C] = &[C::F32, C::I8, C::U8, C::I16, C::U16];
/// Normals under KHR_mesh_quantization: float or normalised signed integers.
pub(super) const FLOAT_OR_SNORM: &[C] = &[C::F32, C::I8, C::I16];

pub(super) struct Loader<'a> {
    pub(super) path: PathBuf,
    pub(super) root: &'a json::Root,
    pub(super) buffers: &'a Buffers<'a>,
    pub(super) warnings: Vec<String>,
    pub(super) textures: Vec<TextureRgba8>,
    /// glTF texture index -> index in `textures` (None: could not be decoded, warned).
    pub(super) texture_slots: HashMap<usize, Option<usize>>,
    /// KHR_mesh_quantization is used: positions and UVs may be (un)normalised integers,
    /// dequantised by the node transforms.
    pub(super) quantized: bool,
}

pub(super) fn checked<V: Copy>(c: &Checked<V>) -> Option<V> {
    match c {
        Checked::Valid(v) => Some(*v),
        Checked::Invalid => None,
    }
}

/// "mesh 3 'Cylinder'" or "mesh 3".
pub(super) fn label(kind: &str, index: usize, name: Option<&str>) -> String {
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
    pub(super) fn extension_warnings(&mut self) {
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

    pub(super) fn fail(&self, problem: impl Into<String>) -> Error {
        Error::Asset { path: self.path.clone(), problem: problem.into() }
    }

    pub(super) fn accessor(&self, index: usize, what: &str, types: &[T], components: &[C]) -> Result<Dense> {
        accessors::read_accessor(self.root, self.buffers, index, types, components)
            .map_err(|e| self.fail(format!("{what}: {e}")))
    }

    /// A position or texture coordinate: float, or under KHR_mesh_quantization any 8- or 16-bit
    /// integer, normalised or not.
    pub(super) fn quantizable_floats(&self, index: usize, what: &str, ty: T, plain: &[C]) -> Result<Vec<f32>> {
        if !self.quantized {
            return self.floats(index, what, ty, plain);
        }
        Ok(self.accessor(index, what, &[ty], &[C::F32, C::I8, C::U8, C::I16, C::U16])?.floats())
    }

    /// A float attribute; integer storage must be normalised.
    pub(super) fn floats(&self, index: usize, what: &str, ty: T, components: &[C]) -> Result<Vec<f32>> {
        let dense = self.accessor(index, what, &[ty], components)?;
        if dense.component != C::F32 && !dense.normalized {
            return Err(self.fail(format!(
                "{what}: accessor {index} stores {} without `normalized: true`",
                accessors::component_name(dense.component)
            )));
        }
        Ok(dense.floats())
    }

    pub(super) fn model(&mut self) -> Result<Model> {
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
        // Checked (a broken camera refuses the file); only the tests read them back.
        let _cameras = self.cameras()?;
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
            #[cfg(test)]
            cameras: _cameras,
            lights,
            warnings: std::mem::take(&mut self.warnings),
        })
    }
}
