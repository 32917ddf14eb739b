//! Meshes and their primitives: vertex attributes read from accessors and checked (counts,
//! finite values, normalisation), indices in range, strips and fans turned into lists, missing
//! normals computed.

use glam::{Vec2, Vec3, Vec4};
use gltf::json;
use json::accessor::{ComponentType as C, Type as T};
use json::validation::Checked;

use super::loader::{checked, label, Loader, FLOAT_OR_SNORM, FLOAT_OR_UNORM};
use crate::error::Result;
use crate::scene::model::{Material, Mesh, Primitive};
use crate::scene::normals::smooth_normals;

impl Loader<'_> {
    pub(super) fn meshes(&mut self, materials: &[Material]) -> Result<Vec<Mesh>> {
        let mut out = Vec::with_capacity(self.root.meshes.len());
        for (m, mesh) in self.root.meshes.iter().enumerate() {
            let mesh_label = label("mesh", m, mesh.name.as_deref());
            let mut primitives = Vec::with_capacity(mesh.primitives.len());
            for (p, prim) in mesh.primitives.iter().enumerate() {
                let what = format!("{mesh_label} primitive {p}");
                if let Some(primitive) = self.primitive(&what, prim, materials)? {
                    primitives.push(primitive);
                }
            }
            out.push(Mesh { name: mesh.name.clone(), primitives });
        }
        Ok(out)
    }

    /// One primitive, read and checked; `None` (with a warning naming it) for one that draws
    /// nothing: not triangles, no positions, no whole triangle.
    fn primitive(
        &mut self,
        what: &str,
        prim: &json::mesh::Primitive,
        materials: &[Material],
    ) -> Result<Option<Primitive>> {
        use json::mesh::{Mode, Semantic};
        let mode = checked(&prim.mode).unwrap_or(Mode::Triangles);
        if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            self.warnings.push(format!("{what}: {mode:?} primitive skipped (only triangles are drawn)"));
            return Ok(None);
        }
        if prim.extensions.as_ref().is_some_and(|e| e.others.contains_key(DRACO)) {
            self.draco_fallback(what, prim)?;
        }
        let Some(pos_index) = attribute(prim, Semantic::Positions) else {
            self.warnings.push(format!("{what}: no POSITION attribute; skipped"));
            return Ok(None);
        };
        if prim.targets.as_ref().is_some_and(|t| !t.is_empty()) {
            self.warnings.push(format!("{what}: morph targets are not supported and were ignored"));
        }
        let positions = self.positions(what, pos_index)?;
        let n = positions.len();
        let normals = self.normals(what, prim, n)?;
        let uv0 = self.tex_coords(what, prim, 0, n)?;
        let uv1 = self.tex_coords(what, prim, 1, n)?;
        let colors = self.colours(what, prim, n)?;
        let (joints, weights) = self.skin_of(what, prim, n)?;
        let (indices, _source_index_width) = self.indices(what, prim, n)?;
        let indices = self.triangle_list(what, mode, indices);
        if indices.is_empty() {
            // Nothing to draw, and an empty index buffer is nothing a GPU can upload.
            self.warnings.push(format!("{what}: no whole triangle ({n} vertices); skipped"));
            return Ok(None);
        }
        let material = prim.material.map(|m| m.value());
        self.check_material(what, material, materials, [uv0.is_some(), uv1.is_some()])?;
        let (normals, _normals_generated) = match normals {
            Some(normals) => (normals, false),
            None => (smooth_normals(&positions, &indices), true),
        };
        Ok(Some(Primitive {
            positions,
            normals,
            #[cfg(test)]
            normals_generated: _normals_generated,
            uv0,
            uv1,
            colors,
            joints,
            weights,
            indices,
            #[cfg(test)]
            source_index_width: _source_index_width,
            material,
        }))
    }

    /// POSITION, every value finite.
    fn positions(&mut self, what: &str, index: usize) -> Result<Vec<Vec3>> {
        let flat = self.quantizable_floats(index, &format!("{what} POSITION"), T::Vec3, &[C::F32])?;
        let positions: Vec<Vec3> = flat.chunks_exact(3).map(Vec3::from_slice).collect();
        if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
            return Err(self.fail(format!(
                "{what}: POSITION of vertex {v} is not finite ({})",
                positions.get(v).copied().unwrap_or_default()
            )));
        }
        Ok(positions)
    }

    /// An attribute's count checked against POSITION's `n`.
    fn same_count(&self, what: &str, name: &str, count: usize, n: usize) -> Result<()> {
        if count == n {
            Ok(())
        } else {
            Err(self.fail(format!("{what}: {name} has {count} elements but POSITION has {n}")))
        }
    }

    /// NORMAL, finite, normalised (a zero normal becomes +Z); `None` when absent.
    fn normals(&mut self, what: &str, prim: &json::mesh::Primitive, n: usize) -> Result<Option<Vec<Vec3>>> {
        let Some(i) = attribute(prim, json::mesh::Semantic::Normals) else {
            return Ok(None);
        };
        let name = format!("{what} NORMAL");
        let components: &[C] = if self.quantized { FLOAT_OR_SNORM } else { &[C::F32] };
        let flat = self.floats(i, &name, T::Vec3, components)?;
        let normals: Vec<Vec3> = flat.chunks_exact(3).map(Vec3::from_slice).collect();
        self.same_count(what, "NORMAL", normals.len(), n)?;
        if let Some(v) = normals.iter().position(|p| !p.is_finite()) {
            return Err(self.fail(format!("{name} of vertex {v} is not finite")));
        }
        Ok(Some(normals.into_iter().map(|v| v.try_normalize().unwrap_or(Vec3::Z)).collect()))
    }

    /// TEXCOORD_`set`, when present.
    fn tex_coords(
        &mut self,
        what: &str,
        prim: &json::mesh::Primitive,
        set: u32,
        n: usize,
    ) -> Result<Option<Vec<Vec2>>> {
        let Some(i) = attribute(prim, json::mesh::Semantic::TexCoords(set)) else {
            return Ok(None);
        };
        let name = format!("TEXCOORD_{set}");
        let flat = self.quantizable_floats(i, &format!("{what} {name}"), T::Vec2, FLOAT_OR_UNORM)?;
        let uvs: Vec<Vec2> = flat.chunks_exact(2).map(Vec2::from_slice).collect();
        self.same_count(what, &name, uvs.len(), n)?;
        Ok(Some(uvs))
    }

    /// COLOR_0 as RGBA (an RGB colour gets alpha 1), when present.
    fn colours(&mut self, what: &str, prim: &json::mesh::Primitive, n: usize) -> Result<Option<Vec<Vec4>>> {
        let Some(i) = attribute(prim, json::mesh::Semantic::Colors(0)) else {
            return Ok(None);
        };
        let name = format!("{what} COLOR_0");
        let dense = self.accessor(i, &name, &[T::Vec3, T::Vec4], FLOAT_OR_UNORM)?;
        if dense.component != C::F32 && !dense.normalized {
            return Err(self.fail(format!("{name}: integer colours must be normalized")));
        }
        let k = dense.components();
        let colors: Vec<Vec4> = dense
            .floats()
            .chunks_exact(k)
            .map(|c| match c {
                [r, g, b] => Vec4::new(*r, *g, *b, 1.0),
                _ => Vec4::from_slice(c),
            })
            .collect();
        self.same_count(what, "COLOR_0", colors.len(), n)?;
        Ok(Some(colors))
    }

    /// JOINTS_n and WEIGHTS_n, every set of them; none (with a warning) when one comes without
    /// the other.
    fn skin_of(&mut self, what: &str, prim: &json::mesh::Primitive, n: usize) -> Result<OptionalSkin> {
        use json::mesh::Semantic;
        match (attribute(prim, Semantic::Joints(0)), attribute(prim, Semantic::Weights(0))) {
            (Some(j), Some(w)) => {
                // Further sets (JOINTS_1/WEIGHTS_1, ...) carry influences 5 to 8 and beyond.
                let mut sets = vec![(j, w)];
                while let (Some(j), Some(w)) = (
                    attribute(prim, Semantic::Joints(sets.len() as u32)),
                    attribute(prim, Semantic::Weights(sets.len() as u32)),
                ) {
                    sets.push((j, w));
                }
                let (joints, weights) = self.skin_attributes(what, &sets, n)?;
                Ok((Some(joints), Some(weights)))
            }
            (None, None) => Ok((None, None)),
            _ => {
                self.warnings.push(format!("{what}: JOINTS_0 without WEIGHTS_0 or the reverse; drawn unskinned"));
                Ok((None, None))
            }
        }
    }

    /// The indices, in range of the `n` vertices, and their width in the file (`None`: the
    /// primitive has none, and its vertices are taken in order).
    fn indices(&mut self, what: &str, prim: &json::mesh::Primitive, n: usize) -> Result<(Vec<u32>, Option<u8>)> {
        let Some(i) = prim.indices else {
            let n32 =
                u32::try_from(n).map_err(|_| self.fail(format!("{what}: {n} vertices do not fit u32 indices")))?;
            return Ok(((0..n32).collect(), None));
        };
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
        Ok((indices, Some(width)))
    }

    /// Strips and fans as lists; a list's incomplete last triangle dropped, with a warning.
    fn triangle_list(&mut self, what: &str, mode: json::mesh::Mode, mut indices: Vec<u32>) -> Vec<u32> {
        use json::mesh::Mode;
        match mode {
            Mode::TriangleStrip => strip_to_list(&indices),
            Mode::TriangleFan => fan_to_list(&indices),
            _ => {
                let extra = indices.len() % 3;
                if extra != 0 {
                    // Valid glTF (the validator only warns): the incomplete last triangle is
                    // not drawn, as a GPU would not draw it.
                    self.warnings.push(format!(
                        "{what}: {} vertices/indices are not a whole number of triangles; the last {extra} \
                         are ignored",
                        indices.len()
                    ));
                    indices.truncate(indices.len() - extra);
                }
                indices
            }
        }
    }

    /// The material exists, and each texture of it reads a texture coordinate set the
    /// primitive has (`has_uv`: TEXCOORD_0, TEXCOORD_1), else a warning names it.
    fn check_material(
        &mut self,
        what: &str,
        material: Option<usize>,
        materials: &[Material],
        has_uv: [bool; 2],
    ) -> Result<()> {
        if let Some(m) = material.filter(|&m| m >= materials.len()) {
            return Err(self.fail(format!("{what}: material {m} does not exist")));
        }
        let textures = material.and_then(|m| materials.get(m)).into_iter().flat_map(|m| {
            [("base colour", m.base_color_texture), ("emissive", m.emissive_texture)]
                .into_iter()
                .filter_map(|(slot, t)| Some((slot, t?)))
        });
        for (slot, texture) in textures {
            let present = has_uv.get(texture.tex_coord as usize).copied().unwrap_or(false);
            if !present {
                self.warnings.push(format!(
                    "{what}: its material's {slot} texture reads TEXCOORD_{}, which the primitive lacks",
                    texture.tex_coord
                ));
            }
        }
        Ok(())
    }
}

/// A primitive's joints and weights, when it is skinned.
type OptionalSkin = (Option<Vec<[u16; 4]>>, Option<Vec<[f32; 4]>>);

/// The accessor index of `prim`'s attribute `semantic`, when it has one.
fn attribute(prim: &json::mesh::Primitive, semantic: json::mesh::Semantic) -> Option<usize> {
    prim.attributes.get(&Checked::Valid(semantic)).map(|i| i.value())
}

const DRACO: &str = "KHR_draco_mesh_compression";

impl Loader<'_> {
    /// No Draco decoder is used here (no well-kept Rust crate exists). A primitive compressed
    /// with it is drawn from its uncompressed fallback, which the extension requires when it is
    /// not listed as required; without that fallback (accessors with no bufferView, which would
    /// read as zeros) the file is refused, naming the extension.
    fn draco_fallback(&mut self, what: &str, prim: &json::mesh::Primitive) -> Result<()> {
        let accessors = prim.attributes.values().chain(prim.indices.iter());
        let stored = accessors
            .map(|a| self.root.accessors.get(a.value()))
            .all(|a| a.is_some_and(|a| a.buffer_view.is_some() || a.sparse.is_some()));
        if !stored {
            return Err(self.fail(format!(
                "{what} is compressed with {DRACO}, which nostencil cannot decode, and has no uncompressed \
                 fallback; re-export without Draco compression"
            )));
        }
        self.warnings.push(format!("{what}: {DRACO} is not decoded; its uncompressed fallback is drawn"));
        Ok(())
    }
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
