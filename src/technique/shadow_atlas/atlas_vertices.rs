//! The atlas vertices: per vertex its position, normal, atlas UV and material inputs, laid out
//! once per mesh; a skinned mesh's posed again on the CPU from its layout as its pose moves
//! (`PosedLayout`), or, skinning on the GPU, uploaded once in the bind pose with each vertex's
//! joints and weights for the pipelines' skinned twins.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::atlas::MeshAtlas;
use crate::error::Result;
use crate::gpu::Gpu;
use crate::render::{scene_vertices, skinned_vertices, GpuMesh};
use crate::scene::objects::SceneMesh;
use crate::scene::{JointPalettes, Scene, SceneSkin};

/// Per mesh: the mesh vertex and the atlas UV of each GPU vertex, to lay a re-posed skin out
/// again.
pub(super) struct PosedLayout {
    sources: Vec<u32>,
    uvs: Vec<Vec2>,
    /// The material's inputs of each GPU vertex (UV0, UV1, COLOR_0), gathered once.
    surface: Vec<[f32; 8]>,
    /// The atlas mesh's triangles.
    indices: Vec<u32>,
}

impl PosedLayout {
    /// `mesh`'s layout in its atlas `atlas`.
    pub(super) fn of(mesh: &SceneMesh, atlas: &MeshAtlas) -> Self {
        PosedLayout {
            sources: atlas.source_vertices.clone(),
            uvs: atlas.uvs.clone(),
            surface: surface_of(mesh, &atlas.source_vertices),
            indices: atlas.indices.clone(),
        }
    }

    /// The atlas vertices of the mesh as `atlas` (its layout) lays it out, unposed.
    pub(super) fn laid_out(&self, atlas: &MeshAtlas) -> Vec<[f32; 16]> {
        atlas_vertices(&atlas.positions, &atlas.normals, &self.uvs, &self.surface)
    }

    /// The atlas vertices of `skin`'s current pose.
    pub(super) fn posed(&self, skin: &SceneSkin) -> Vec<[f32; 16]> {
        let (positions, normals) = skin.posed_positions_normals();
        let pick = |list: &[Vec3], fallback: Vec3| -> Vec<Vec3> {
            self.sources.iter().map(|&v| list.get(v as usize).copied().unwrap_or(fallback)).collect()
        };
        atlas_vertices(&pick(&positions, Vec3::ZERO), &pick(&normals, Vec3::Y), &self.uvs, &self.surface)
    }
}

/// Position, normal, atlas UV and the material's inputs per vertex, interleaved as
/// `passes::ATLAS_VERTEX` says.
pub(crate) fn atlas_vertices(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    surface: &[[f32; 8]],
) -> Vec<[f32; 16]> {
    (0..positions.len())
        .map(|i| {
            let (p, n, uv) = (positions[i], normals.get(i).copied().unwrap_or(Vec3::Y), uvs[i]);
            let s = surface.get(i).copied().unwrap_or([0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]);
            [p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y, s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7]]
        })
        .collect()
}

/// Per object skinned on the GPU, its mesh's atlas vertices in the skin's bind pose, each with
/// the joints (moved to the object's palette) and weights of the vertex it comes from.
pub(super) fn upload_bind_poses(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    layouts: &[PosedLayout],
    palettes: &JointPalettes,
) -> Result<Vec<Option<GpuMesh>>> {
    scene
        .objects
        .iter()
        .zip(&palettes.first_joint)
        .map(|(object, first)| {
            let (Some(skin), Some(first), Some(source), Some(layout)) =
                (&object.skin, first, scene.meshes.get(object.mesh), layouts.get(object.mesh))
            else {
                return Ok(None);
            };
            // The bind pose's vertices with their joints checked and moved (one per mesh vertex).
            let skinned = skinned_vertices(&object.name, source, skin, *first)?;
            let pick = |v: u32| skinned.get(v as usize);
            let positions: Vec<Vec3> =
                layout.sources.iter().map(|&v| pick(v).map_or(Vec3::ZERO, |s| s.scene.position.into())).collect();
            let normals: Vec<Vec3> =
                layout.sources.iter().map(|&v| pick(v).map_or(Vec3::Y, |s| s.scene.normal.into())).collect();
            let atlas = atlas_vertices(&positions, &normals, &layout.uvs, &layout.surface);
            let vertices: Vec<SkinnedAtlasVertex> = atlas
                .into_iter()
                .zip(&layout.sources)
                .map(|(atlas, &v)| {
                    let (joints, weights) = pick(v).map_or(([0; 4], [0.0; 4]), |s| (s.joints, s.weights));
                    SkinnedAtlasVertex { atlas, joints, weights }
                })
                .collect();
            let name = format!("{} atlas vertices (bind pose)", object.name);
            GpuMesh::from_raw(gpu, &name, &vertices, &layout.indices).map(Some)
        })
        .collect()
}

/// One vertex of `VertexLayout::SKINNED_ATLAS`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SkinnedAtlasVertex {
    atlas: [f32; 16],
    joints: [u16; 4],
    weights: [f32; 4],
}

/// UV0, UV1 and COLOR_0 of `mesh`'s vertices `sources` (one per atlas vertex).
pub(crate) fn surface_of(mesh: &SceneMesh, sources: &[u32]) -> Vec<[f32; 8]> {
    let vertices = scene_vertices(mesh, &mesh.data.positions, &mesh.data.normals);
    sources
        .iter()
        .map(|&v| {
            let s = vertices.get(v as usize);
            let (uv0, uv1, c) = s.map_or(([0.0; 2], [0.0; 2], [1.0; 4]), |s| (s.uv0, s.uv1, s.colour));
            [uv0[0], uv0[1], uv1[0], uv1[1], c[0], c[1], c[2], c[3]]
        })
        .collect()
}
