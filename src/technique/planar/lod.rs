//! Low-poly shadow casters (seed 001: "a mesh shadow draws the mesh once more, so give the
//! shadow a mesh with fewer polygons"): each caster's triangles simplified with meshoptimizer
//! into an index buffer over the caster's own vertices, so a skinned caster keeps its skin and
//! nothing but the indices is uploaded.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;
use glam::Vec3;

use crate::error::{Error, Result};
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::scene::Scene;

/// The largest deviation meshoptimizer may introduce, relative to the mesh's extent: a shadow's
/// outline may move by about this fraction of the caster's size. The triangle ratio is a target
/// that this limit can stop short of (a box stays a box).
pub const MAX_RELATIVE_ERROR: f32 = 0.05;

/// `indices` (triangles over `positions`) simplified to about `ratio` of their triangles. Only
/// positions matter for a shadow, so vertices split for normals or UVs are welded first (else
/// every seam would be a border meshoptimizer must keep); the result names one original vertex
/// per welded one.
pub fn simplified_indices(positions: &[Vec3], indices: &[u32], ratio: f32) -> Result<Vec<u32>> {
    let mut welded_of_position: HashMap<[u32; 3], u32> = HashMap::new();
    let mut welded_positions: Vec<Vec3> = Vec::new();
    let mut original_of_welded: Vec<u32> = Vec::new();
    let mut welded_indices = Vec::with_capacity(indices.len());
    for triangle in indices.chunks_exact(3) {
        for &v in triangle {
            let p = *positions
                .get(v as usize)
                .ok_or_else(|| Error::Internal(format!("index {v} beyond {} vertices", positions.len())))?;
            let id = *welded_of_position.entry(p.to_array().map(f32::to_bits)).or_insert_with(|| {
                welded_positions.push(p);
                original_of_welded.push(v);
                (welded_positions.len() - 1) as u32
            });
            welded_indices.push(id);
        }
    }
    if welded_indices.is_empty() {
        return Ok(Vec::new());
    }
    let target = ((welded_indices.len() as f64 * ratio as f64) as usize / 3 * 3).max(3);
    let adapter = meshopt::VertexDataAdapter::new(bytemuck::cast_slice(&welded_positions), 12, 0)
        .map_err(|e| Error::Internal(format!("meshoptimizer refused the positions: {e}")))?;
    let simplified =
        meshopt::simplify(&welded_indices, &adapter, target, MAX_RELATIVE_ERROR, meshopt::SimplifyOptions::None, None);
    Ok(simplified.into_iter().map(|w| original_of_welded[w as usize]).collect())
}

/// One caster's simplified triangles on the GPU.
pub struct CasterLod {
    pub indices: Buffer,
    pub index_count: u32,
}

/// Every caster's simplified triangles (`None` for receivers), and how many triangles the full
/// and simplified casters have.
pub struct CasterLods {
    pub per_object: Vec<Option<CasterLod>>,
    pub full_triangles: usize,
    pub lod_triangles: usize,
}

impl CasterLods {
    /// Simplifies every caster (a skinned one in its bind pose, which its skin then moves).
    pub fn build(gpu: &Arc<Gpu>, scene: &Scene, receivers: &[bool], ratio: f32) -> Result<Self> {
        let (mut full_triangles, mut lod_triangles) = (0, 0);
        let mut per_object = Vec::with_capacity(scene.objects.len());
        for (index, object) in scene.objects.iter().enumerate() {
            let Some(mesh) = scene.meshes.get(object.mesh).filter(|_| !receivers[index]) else {
                per_object.push(None);
                continue;
            };
            let positions = object.skin.as_ref().map_or(&mesh.data.positions, |skin| &skin.positions);
            let indices = simplified_indices(positions, &mesh.data.indices, ratio)
                .map_err(|e| Error::Mesh { mesh: mesh.name.clone(), problem: format!("shadow LOD: {e}") })?;
            full_triangles += mesh.data.indices.len() / 3;
            lod_triangles += indices.len() / 3;
            per_object.push(if indices.is_empty() {
                None
            } else {
                Some(CasterLod {
                    indices: Buffer::device_local(
                        gpu,
                        &format!("{} shadow LOD indices", object.name),
                        &indices,
                        vk::BufferUsageFlags::INDEX_BUFFER,
                    )?,
                    index_count: indices.len() as u32,
                })
            });
        }
        Ok(CasterLods { per_object, full_triangles, lod_triangles })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn a_torus_loses_most_triangles_and_a_box_none() {
        let torus = shapes::torus(0.8, 0.3, 48, 24).expect("torus");
        let lod = simplified_indices(&torus.positions, &torus.indices, 0.2).expect("lod");
        let (full, kept) = (torus.indices.len() / 3, lod.len() / 3);
        assert!(kept * 4 <= full && kept > 50, "{kept} of {full} triangles kept");
        assert!(lod.iter().all(|&v| (v as usize) < torus.positions.len()));
        // A cube split for normals (24 vertices) welds to 8 corners; it cannot lose a triangle
        // without moving a face by its whole size.
        let cube = shapes::cube(1.0);
        let lod = simplified_indices(&cube.positions, &cube.indices, 0.2).expect("lod");
        assert_eq!(lod.len(), cube.indices.len());
    }
}
