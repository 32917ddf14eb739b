//! Rigid casters' doubled vertices (Doom 3 BFG's shadow vertices): each welded position at
//! w = 1 and again at w = 0, which `shaders/shadow_volume.vert` pushes away from the light.
//! Uploaded once per mesh at build, so that a frame whose light or caster moved writes only
//! the indices the CPU chose (skinned casters upload their posed copy with them).

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use super::casters::Caster;
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
        let (mut buffers, mut of_caster) = (Vec::new(), Vec::with_capacity(casters.len()));
        let mut of_scene_mesh: HashMap<usize, usize> = HashMap::new();
        let mut doubled = Vec::new();
        for caster in casters {
            let object = &scene.objects[caster.object];
            if object.skin.is_some() {
                of_caster.push(None);
                continue;
            }
            if let Some(&buffer) = of_scene_mesh.get(&object.mesh) {
                of_caster.push(Some(buffer));
                continue;
            }
            let positions = &caster.mesh.welded.positions[..caster.mesh.adjacency.vertex_count];
            doubled_vertices(positions, &mut doubled);
            let name = format!("shadow volume vertices ({})", scene.meshes[object.mesh].name);
            buffers.push(Buffer::device_local(gpu, &name, &doubled, vk::BufferUsageFlags::VERTEX_BUFFER)?);
            of_scene_mesh.insert(object.mesh, buffers.len() - 1);
            of_caster.push(Some(buffers.len() - 1));
        }
        Ok(DoubledVertices { buffers, of_caster })
    }

    /// Caster `caster`'s doubled vertices, if it is rigid.
    pub fn of_caster(&self, caster: usize) -> Option<&Buffer> {
        self.buffers.get((*self.of_caster.get(caster)?)?)
    }
}
