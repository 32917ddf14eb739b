//! Rigid casters' doubled vertices (Doom 3 BFG's shadow vertices): each welded position at
//! w = 1 and again at w = 0, which `shaders/shadow_volume.vert` pushes away from the light.
//! Uploaded once per mesh at build, so that a frame whose light or caster moved writes only
//! the indices the CPU chose (skinned casters upload their posed copy with them).

use std::sync::Arc;

use ash::vk;

use super::casters::{per_rigid_mesh, Caster};
use crate::error::Result;
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::mesh::shadow_volume::doubled_vertices;
use crate::scene::Scene;

/// Every rigid caster's doubled vertices, one buffer per scene mesh.
pub struct DoubledVertices {
    buffers: Vec<Buffer>,
    /// Per caster: its buffer, or `None` for a skinned caster.
    of_caster: Vec<Option<usize>>,
}

impl DoubledVertices {
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene, casters: &[Caster]) -> Result<Self> {
        let mut doubled = Vec::new();
        let (buffers, of_caster) = per_rigid_mesh(scene, casters, |caster| {
            let positions = &caster.mesh.welded.positions[..caster.mesh.adjacency.vertex_count];
            doubled_vertices(positions, &mut doubled);
            let name = format!("shadow volume vertices ({})", scene.meshes[scene.objects[caster.object].mesh].name);
            Buffer::device_local(gpu, &name, &doubled, vk::BufferUsageFlags::VERTEX_BUFFER).map(Some)
        })?;
        Ok(DoubledVertices { buffers, of_caster })
    }

    /// Caster `caster`'s doubled vertices, if it is rigid.
    pub fn of_caster(&self, caster: usize) -> Option<&Buffer> {
        self.buffers.get((*self.of_caster.get(caster)?)?)
    }
}
