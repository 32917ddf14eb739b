//! Casters' doubled vertices (Doom 3 BFG's shadow vertices): each welded position at w = 1 and
//! again at w = 0, which `shaders/shadow_volume.vert` pushes away from the light. Uploaded once
//! at build, so that a frame whose light or caster moved writes only the indices the CPU chose:
//! every rigid mesh's one after another in one buffer, which a volume pass binds once (each
//! volume's draws start at its mesh's first vertex), and per skinned caster skinned on the GPU
//! its bind pose with its joints and weights, which the shader's skinned twin poses. (A skinned
//! caster posed on the CPU uploads its posed copy with its indices instead.)

use std::sync::Arc;

use ash::vk;
use glam::Vec4;

use super::casters::{per_rigid_mesh, Caster};
use crate::error::{Error, Result};
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::mesh::shadow_volume::doubled_vertices;
use crate::scene::{JointPalettes, Scene};

/// Every caster's doubled vertices uploaded at build.
pub struct DoubledVertices {
    /// Every rigid mesh's doubled vertices (`None` without a rigid caster).
    rigid: Option<Buffer>,
    /// Per caster: the first vertex of its rigid mesh's in `rigid`, or `None` for a skinned
    /// caster.
    rigid_first: Vec<Option<i32>>,
    /// Per caster skinned on the GPU: its bind pose, doubled (`VertexLayout::SKINNED_POSITION4`).
    skinned: Vec<Option<Buffer>>,
}

/// Where a caster's doubled vertices are, and how they are drawn.
pub enum Doubled<'a> {
    /// Placed by the caster's transform alone: its mesh's vertices start at `first_vertex`
    /// of the buffer all rigid meshes share (the draws' vertex offset).
    Rigid { vertices: &'a Buffer, first_vertex: i32 },
    /// Skinned by the frame's joint palettes (the pipeline's skinned twin draws them).
    Skinned(&'a Buffer),
}

/// One vertex of `VertexLayout::SKINNED_POSITION4`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SkinnedDoubledVertex {
    position: [f32; 4],
    joints: [u16; 4],
    weights: [f32; 4],
}

impl DoubledVertices {
    /// `palettes`: where the skinned objects' palettes lie when they are skinned on the GPU.
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene, casters: &[Caster], palettes: Option<&JointPalettes>) -> Result<Self> {
        let (mut all, mut doubled) = (Vec::<Vec4>::new(), Vec::new());
        let (firsts, of_caster) = per_rigid_mesh(scene, casters, |caster| {
            let positions = &caster.mesh.welded.positions[..caster.mesh.adjacency.vertex_count];
            doubled_vertices(positions, &mut doubled);
            let first = i32::try_from(all.len()).map_err(|_| {
                Error::InvalidInput(format!(
                    "the casters' doubled vertices pass {} (a draw's vertex offset is 32-bit)",
                    i32::MAX
                ))
            })?;
            all.extend_from_slice(&doubled);
            Ok(Some(first))
        })?;
        let rigid = if all.is_empty() {
            None
        } else {
            Some(Buffer::device_local(gpu, "shadow volume vertices", &all, vk::BufferUsageFlags::VERTEX_BUFFER)?)
        };
        let rigid_first = of_caster.iter().map(|mesh| mesh.map(|mesh| firsts[mesh])).collect();
        let skinned = match palettes {
            Some(palettes) => casters.iter().map(|c| upload_skinned(gpu, scene, c, palettes)).collect::<Result<_>>()?,
            None => Vec::new(),
        };
        Ok(DoubledVertices { rigid, rigid_first, skinned })
    }

    /// Caster `caster`'s doubled vertices uploaded at build (none for a skinned caster posed on
    /// the CPU, whose posed copy the frame uploads).
    pub fn of_caster(&self, caster: usize) -> Option<Doubled<'_>> {
        if let Some(buffer) = self.skinned.get(caster).and_then(Option::as_ref) {
            return Some(Doubled::Skinned(buffer));
        }
        let first_vertex = (*self.rigid_first.get(caster)?)?;
        self.rigid.as_ref().map(|vertices| Doubled::Rigid { vertices, first_vertex })
    }

    /// Whether caster `caster` is skinned on the GPU.
    pub fn skinned_on_gpu(&self, caster: usize) -> bool {
        self.skinned.get(caster).is_some_and(Option::is_some)
    }
}

/// A skinned caster's welded bind pose, doubled as `doubled_vertices` doubles positions, each
/// welded vertex with the joints (moved to its palette) and weights of the vertex it stands
/// for. The apex has no weights: the shader starts it at the push's posed centroid.
fn upload_skinned(gpu: &Arc<Gpu>, scene: &Scene, caster: &Caster, palettes: &JointPalettes) -> Result<Option<Buffer>> {
    let object = &scene.objects[caster.object];
    let (Some(skin), Some(Some(first))) = (&object.skin, palettes.first_joint.get(caster.object)) else {
        return Ok(None);
    };
    let welded = &caster.mesh.welded;
    let count = caster.mesh.adjacency.vertex_count;
    let vertex = |w: f32| {
        move |&original: &u32| -> Result<SkinnedDoubledVertex> {
            let v = original as usize;
            let (Some(p), Some(j), Some(weights)) = (skin.positions.get(v), skin.joints.get(v), skin.weights.get(v))
            else {
                return Err(Error::Mesh {
                    mesh: object.name.clone(),
                    problem: format!("vertex {v} has no bind-pose position, joints or weights"),
                });
            };
            let joints = j.map(|j| u16::try_from(u32::from(j) + first).unwrap_or(u16::MAX));
            Ok(SkinnedDoubledVertex { position: p.extend(w).to_array(), joints, weights: *weights })
        }
    };
    let representatives = &welded.representative[..count.min(welded.representative.len())];
    let mut vertices: Vec<SkinnedDoubledVertex> = representatives
        .iter()
        .map(vertex(1.0))
        .chain(representatives.iter().map(vertex(0.0)))
        .collect::<Result<_>>()?;
    vertices.push(SkinnedDoubledVertex { position: [0.0; 4], joints: [0; 4], weights: [0.0; 4] });
    let name = format!("shadow volume vertices ({}, bind pose)", object.name);
    Buffer::device_local(gpu, &name, &vertices, vk::BufferUsageFlags::VERTEX_BUFFER).map(Some)
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_skinned_vertex_matches_its_layout() {
        assert_eq!(
            crate::pipeline::VertexLayout::SKINNED_POSITION4.stride() as usize,
            std::mem::size_of::<super::SkinnedDoubledVertex>()
        );
    }
}
