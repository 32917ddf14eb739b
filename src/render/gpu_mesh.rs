//! Meshes uploaded to device-local vertex and index buffers, and skinned meshes' posed copies
//! (one per frame slot, host-visible, rewritten in place).

use std::sync::Arc;

use ash::vk;
use bytemuck::Pod;
use glam::{Vec2, Vec3, Vec4};

use super::materials::GpuMaterials;
use super::per_slot::slot_copy;
use crate::error::Result;
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::scene::objects::SceneMesh;
use crate::scene::{Scene, SlotPoses};

pub struct GpuMesh {
    /// The mesh as uploaded (device-local).
    pub vertices: Buffer,
    /// Per frame slot, a skinned mesh's posed vertices (host-visible, written in place) once it
    /// moved from the pose it was uploaded in; empty for a mesh that never moved.
    posed: Vec<Option<Buffer>>,
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
            posed: Vec::new(),
        })
    }

    /// Writes `vertices` (the mesh posed, same layout and count) into frame slot `slot`'s copy,
    /// made host-visible at its first pose and written in place after it. No frame in flight
    /// may read that copy.
    pub fn write_posed<V: Pod>(&mut self, gpu: &Arc<Gpu>, slot: usize, name: &str, vertices: &[V]) -> Result<()> {
        match slot_copy(&mut self.posed, slot, || Ok(None))? {
            Some(buffer) => buffer.rewrite(gpu, name, vertices, vk::BufferUsageFlags::VERTEX_BUFFER),
            copy @ None => {
                *copy = Some(Buffer::with_data(gpu, name, vertices, vk::BufferUsageFlags::VERTEX_BUFFER)?);
                Ok(())
            }
        }
    }

    /// The vertices frame slot `slot` draws: its posed copy, else the mesh as uploaded.
    pub fn vertices_in(&self, slot: usize) -> &Buffer {
        self.posed.get(slot).and_then(Option::as_ref).unwrap_or(&self.vertices)
    }
}

/// The scene's meshes on the GPU, in the scene's mesh order, and its materials.
pub struct GpuScene {
    /// `VertexLayout::SCENE` vertices.
    pub meshes: Vec<GpuMesh>,
    pub materials: GpuMaterials,
    /// Per frame slot, the pose its copy of the skinned objects' vertices holds.
    posed: SlotPoses,
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
        Ok(GpuScene { meshes, materials, posed: SlotPoses::new(scene) })
    }

    /// Re-poses the skinned objects whose palette changed since frame slot `slot`'s copies
    /// were posed (`Scene::pose_at` moves palettes, not meshes): skinned on the CPU, written
    /// into that slot's host-visible copy (`GpuMesh::write_posed`), which the slot's draws read
    /// (`FrameRecorder::draw_mesh`). The frame that last used `slot` must be complete; the other
    /// slots' copies may still be read by frames in flight.
    pub fn follow_pose(&mut self, gpu: &Arc<Gpu>, scene: &Scene, slot: usize) -> Result<()> {
        for index in self.posed.changed(scene, slot) {
            if let Some((mesh, vertices, name)) = self.posed_vertices(scene, index) {
                mesh.write_posed(gpu, slot, &name, &vertices)?;
            }
        }
        Ok(())
    }

    /// Object `index`'s mesh and its vertices skinned by the object's palette now.
    fn posed_vertices(&mut self, scene: &Scene, index: usize) -> Option<(&mut GpuMesh, Vec<SceneVertex>, String)> {
        let object = &scene.objects[index];
        let (Some(skin), Some(mesh), Some(source)) =
            (&object.skin, self.meshes.get_mut(object.mesh), scene.meshes.get(object.mesh))
        else {
            return None;
        };
        let (positions, normals) = skin.posed_positions_normals();
        let name = format!("{} vertices (posed)", object.name);
        Some((mesh, scene_vertices(source, &positions, &normals), name))
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
