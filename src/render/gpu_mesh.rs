//! Meshes uploaded to device-local vertex and index buffers.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;

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
}

impl GpuScene {
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene) -> Result<Self> {
        let meshes = scene.meshes.iter().map(|m| GpuMesh::upload(gpu, &m.name, &m.data)).collect::<Result<_>>()?;
        Ok(GpuScene { meshes })
    }
}
