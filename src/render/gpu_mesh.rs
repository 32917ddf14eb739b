//! Meshes uploaded to device-local vertex and index buffers.

use std::sync::Arc;

use ash::vk;
use bytemuck::Pod;
use glam::{Vec2, Vec3, Vec4};

use super::materials::GpuMaterials;
use crate::error::Result;
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::scene::objects::SceneMesh;
use crate::scene::{PoseTracker, Scene};

pub struct GpuMesh {
    pub vertices: Buffer,
    pub indices: Buffer,
    pub index_count: u32,
}

impl GpuMesh {
    /// Any interleaved vertex type (it must match the pipeline's `VertexLayout`).
    pub fn from_raw<V: Pod>(gpu: &Arc<Gpu>, name: &str, vertices: &[V], indices: &[u32]) -> Result<Self> {
        Ok(GpuMesh {
            vertices: Buffer::device_local(
                gpu,
                &format!("{name} vertices"),
                vertices,
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )?,
            indices: Buffer::device_local(
                gpu,
                &format!("{name} indices"),
                indices,
                vk::BufferUsageFlags::INDEX_BUFFER,
            )?,
            index_count: indices.len() as u32,
        })
    }
}

/// The scene's meshes on the GPU, in the scene's mesh order, and its materials.
pub struct GpuScene {
    /// `VertexLayout::SCENE` vertices.
    pub meshes: Vec<GpuMesh>,
    pub materials: GpuMaterials,
    /// The pose the skinned objects' uploaded vertices hold.
    posed: PoseTracker,
}

impl GpuScene {
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene) -> Result<Self> {
        let meshes = scene
            .meshes
            .iter()
            .map(|m| {
                GpuMesh::from_raw(gpu, &m.name, &scene_vertices(m, &m.data.positions, &m.data.normals), &m.data.indices)
            })
            .collect::<Result<_>>()?;
        let materials = GpuMaterials::upload(gpu, scene)?;
        Ok(GpuScene { meshes, materials, posed: PoseTracker::new(scene) })
    }

    /// Rewrites the vertices of every skinned object whose palette changed since they were
    /// uploaded, skinned on the CPU by the new palette (`Scene::pose_at` moves palettes, not
    /// meshes), into a host-visible buffer made at the first pose and written in place after it;
    /// returns those objects. The caller's previous frame must be complete.
    pub fn follow_pose(&mut self, gpu: &Arc<Gpu>, scene: &Scene) -> Result<Vec<usize>> {
        let changed = self.posed.changed(scene);
        for &index in &changed {
            let object = &scene.objects[index];
            let (Some(skin), Some(mesh), Some(source)) =
                (&object.skin, self.meshes.get_mut(object.mesh), scene.meshes.get(object.mesh))
            else {
                continue;
            };
            let (positions, normals) = skin.posed_positions_normals();
            let name = format!("{} vertices (posed)", object.name);
            let vertices = scene_vertices(source, &positions, &normals);
            mesh.vertices.rewrite(gpu, &name, &vertices, vk::BufferUsageFlags::VERTEX_BUFFER)?;
        }
        Ok(changed)
    }
}

/// One vertex of `VertexLayout::SCENE`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SceneVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv0: [f32; 2],
    pub uv1: [f32; 2],
    pub colour: [f32; 4],
}

/// `mesh`'s vertices at `positions` and `normals` (its own, or a posed copy) with its UV sets
/// and COLOR_0; what is missing is zero UV, white colour, +Y normal.
pub fn scene_vertices(mesh: &SceneMesh, positions: &[Vec3], normals: &[Vec3]) -> Vec<SceneVertex> {
    let at = |list: Option<&[Vec2]>, v: usize| list.and_then(|l| l.get(v)).copied().unwrap_or(Vec2::ZERO);
    positions
        .iter()
        .enumerate()
        .map(|(v, &position)| SceneVertex {
            position: position.to_array(),
            normal: normals.get(v).copied().unwrap_or(Vec3::Y).to_array(),
            uv0: at(Some(&mesh.data.uvs), v).to_array(),
            uv1: at(mesh.uv1.as_deref(), v).to_array(),
            colour: mesh.colors.as_ref().and_then(|c| c.get(v)).copied().unwrap_or(Vec4::ONE).to_array(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn scene_vertex_matches_the_scene_layout() {
        assert_eq!(crate::pipeline::VertexLayout::SCENE.stride() as usize, std::mem::size_of::<super::SceneVertex>());
    }
}
