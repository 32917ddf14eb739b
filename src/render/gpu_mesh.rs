//! Meshes uploaded to device-local vertex and index buffers.

use std::sync::Arc;

use ash::vk;
use bytemuck::Pod;
use glam::Vec3;

use crate::error::Result;
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::mesh::MeshData;
use crate::scene::{PoseTracker, Scene};

pub struct GpuMesh {
    pub vertices: Buffer,
    pub indices: Buffer,
    pub index_count: u32,
}

impl GpuMesh {
    /// Interleaved position + normal (the `VertexLayout::POSITION_NORMAL` layout).
    pub fn upload(gpu: &Arc<Gpu>, name: &str, mesh: &MeshData) -> Result<Self> {
        Self::from_raw(gpu, name, &position_normal_vertices(&mesh.positions, &mesh.normals), &mesh.indices)
    }

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

/// The scene's meshes on the GPU, in the scene's mesh order.
pub struct GpuScene {
    pub meshes: Vec<GpuMesh>,
    /// The pose the skinned objects' uploaded vertices hold.
    posed: PoseTracker,
}

impl GpuScene {
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene) -> Result<Self> {
        let meshes = scene.meshes.iter().map(|m| GpuMesh::upload(gpu, &m.name, &m.data)).collect::<Result<_>>()?;
        Ok(GpuScene { meshes, posed: PoseTracker::new(scene) })
    }

    /// Re-uploads the vertices of every skinned object whose palette changed since they were
    /// uploaded, skinned on the CPU by the new palette (`Scene::pose_at` moves palettes, not
    /// meshes); returns those objects. The caller's previous frame must be complete: the old
    /// buffers are dropped.
    pub fn follow_pose(&mut self, gpu: &Arc<Gpu>, scene: &Scene) -> Result<Vec<usize>> {
        let changed = self.posed.changed(scene);
        for &index in &changed {
            let object = &scene.objects[index];
            let (Some(skin), Some(mesh)) = (&object.skin, self.meshes.get_mut(object.mesh)) else { continue };
            let (positions, normals) = skin.posed_positions_normals();
            let name = format!("{} vertices (posed)", object.name);
            let vertices = position_normal_vertices(&positions, &normals);
            mesh.vertices = Buffer::device_local(gpu, &name, &vertices, vk::BufferUsageFlags::VERTEX_BUFFER)?;
        }
        Ok(changed)
    }
}

/// Interleaved position + normal (the `VertexLayout::POSITION_NORMAL` layout); a missing
/// normal is +Y.
fn position_normal_vertices(positions: &[Vec3], normals: &[Vec3]) -> Vec<[Vec3; 2]> {
    positions.iter().zip(normals.iter().chain(std::iter::repeat(&Vec3::Y))).map(|(p, n)| [*p, *n]).collect()
}
