//! Meshes uploaded to device-local vertex and index buffers.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3};

use crate::error::Result;
use crate::gpu::memory::{as_bytes, Buffer};
use crate::gpu::Gpu;
use crate::mesh::MeshData;
use crate::scene::Scene;

pub struct GpuMesh {
    pub vertices: Buffer,
    pub indices: Buffer,
    pub index_count: u32,
}

impl GpuMesh {
    /// Interleaved position + normal (the `VertexLayout::POSITION_NORMAL` layout).
    pub fn upload(gpu: &Arc<Gpu>, name: &str, mesh: &MeshData) -> Result<Self> {
        let interleaved: Vec<[Vec3; 2]> = mesh
            .positions
            .iter()
            .zip(mesh.normals.iter().chain(std::iter::repeat(&Vec3::Y)))
            .map(|(p, n)| [*p, *n])
            .collect();
        Self::from_raw(gpu, name, as_bytes(&interleaved), &mesh.indices)
    }

    pub fn from_raw(gpu: &Arc<Gpu>, name: &str, vertex_bytes: &[u8], indices: &[u32]) -> Result<Self> {
        Ok(GpuMesh {
            vertices: Buffer::device_local(
                gpu,
                &format!("{name} vertices"),
                vertex_bytes,
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )?,
            indices: Buffer::device_local(
                gpu,
                &format!("{name} indices"),
                as_bytes(indices),
                vk::BufferUsageFlags::INDEX_BUFFER,
            )?,
            index_count: indices.len() as u32,
        })
    }
}

/// The scene's meshes on the GPU, in the scene's mesh order.
pub struct GpuScene {
    pub meshes: Vec<GpuMesh>,
    /// Per mesh, the joint palette its vertices were skinned with (skinned objects' meshes).
    palettes: Vec<Option<Vec<Mat4>>>,
}

impl GpuScene {
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene) -> Result<Self> {
        let meshes = scene.meshes.iter().map(|m| GpuMesh::upload(gpu, &m.name, &m.data)).collect::<Result<_>>()?;
        let mut palettes = vec![None; scene.meshes.len()];
        for object in &scene.objects {
            if let (Some(skin), Some(slot)) = (&object.skin, palettes.get_mut(object.mesh)) {
                *slot = Some(skin.joint_matrices.clone());
            }
        }
        Ok(GpuScene { meshes, palettes })
    }

    /// Re-uploads the vertices of every skinned object whose palette changed since its mesh
    /// was uploaded, skinned on the CPU by the new palette (`Scene::pose_at` moves palettes,
    /// not meshes). The caller's previous frame must be complete: the old buffer is dropped.
    pub fn follow_pose(&mut self, gpu: &Arc<Gpu>, scene: &Scene) -> Result<()> {
        for object in &scene.objects {
            let Some(skin) = &object.skin else { continue };
            let (Some(mesh), Some(palette)) = (self.meshes.get_mut(object.mesh), self.palettes.get_mut(object.mesh))
            else {
                continue;
            };
            if palette.as_ref() == Some(&skin.joint_matrices) {
                continue;
            }
            let (positions, normals) = skin.posed_positions_normals();
            let interleaved: Vec<[Vec3; 2]> = positions
                .iter()
                .zip(normals.iter().chain(std::iter::repeat(&Vec3::Y)))
                .map(|(p, n)| [*p, *n])
                .collect();
            let name = format!("{} vertices (posed)", object.name);
            mesh.vertices =
                Buffer::device_local(gpu, &name, as_bytes(&interleaved), vk::BufferUsageFlags::VERTEX_BUFFER)?;
            *palette = Some(skin.joint_matrices.clone());
        }
        Ok(())
    }
}
