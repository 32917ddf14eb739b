//! GPU skinning: a skinned object's bind-pose vertices with four joints and weights each, and its
//! joint palette in a uniform buffer of `MAX_JOINTS` matrices (16 KiB, the mobile
//! profile's whole uniform range) at descriptor set 1 (`shaders/planar_skinning.glsl`).

use std::sync::Arc;

use ash::vk;
use glam::Mat4;
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::pipeline::VertexLayout;
use crate::render::per_slot::slot_copy;
use crate::render::{skinned_vertices, GpuMesh};
use crate::scene::objects::SceneMesh;
use crate::scene::{SceneSkin, MAX_JOINTS};

/// The scene's vertex, then JOINTS_0 and WEIGHTS_0 (`VertexLayout::SKINNED_SCENE`).
pub const SKINNED_LAYOUT: VertexLayout = VertexLayout::SKINNED_SCENE;

/// Bytes of the joint palette: `MAX_JOINTS` mat4 (std140: 64 bytes each).
pub const PALETTE_BYTES: u64 = (MAX_JOINTS * std::mem::size_of::<Mat4>()) as u64;

/// One joint palette and the descriptor set that binds it, a copy per frame slot (frames in
/// flight each read their own).
pub struct Palette {
    gpu: Arc<Gpu>,
    name: String,
    /// Per frame slot, made when that slot first writes the palette (slot 0 with the palette).
    copies: Vec<PaletteCopy>,
}

struct PaletteCopy {
    // Field order: the set is destroyed before the buffer it points at.
    descriptors: DescriptorSet,
    buffer: Buffer,
}

impl PaletteCopy {
    fn new(gpu: &Arc<Gpu>, name: &str) -> Result<Self> {
        let buffer = Buffer::new(
            gpu,
            &format!("{name} joint palette"),
            PALETTE_BYTES,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let descriptors = DescriptorSet::new(
            gpu,
            &[Binding::UniformBuffer {
                buffer: buffer.raw,
                range: PALETTE_BYTES,
                stages: vk::ShaderStageFlags::VERTEX,
            }],
        )?;
        Ok(PaletteCopy { descriptors, buffer })
    }
}

impl Palette {
    pub fn new(gpu: &Arc<Gpu>, name: &str) -> Result<Self> {
        let copies = vec![PaletteCopy::new(gpu, name)?];
        Ok(Palette { gpu: gpu.clone(), name: name.to_owned(), copies })
    }

    /// The set that binds frame slot `slot`'s copy (slot 0's where that slot never wrote one).
    pub fn descriptors(&self, slot: usize) -> &DescriptorSet {
        &self.copies.get(slot).unwrap_or(&self.copies[0]).descriptors
    }

    /// Writes this frame's joint matrices into frame slot `slot`'s copy (unused entries stay as
    /// they were: no vertex uses them). No frame in flight may read that copy.
    pub fn update(&mut self, slot: usize, joint_matrices: &[Mat4]) -> Result<()> {
        if joint_matrices.len() > MAX_JOINTS {
            return Err(Error::InvalidInput(format!(
                "'{}' has {} joints; the GPU palette holds at most {MAX_JOINTS}",
                self.name,
                joint_matrices.len()
            )));
        }
        let (gpu, name) = (&self.gpu, &self.name);
        slot_copy(&mut self.copies, slot, || PaletteCopy::new(gpu, name))?.buffer.write(0, joint_matrices)
    }
}

/// A skinned object on the GPU: its bind-pose mesh and its palette.
pub struct SkinnedMesh {
    pub mesh: GpuMesh,
    pub palette: Palette,
}

impl SkinnedMesh {
    /// `source` is the object's scene mesh: its indices, UV sets and colours.
    pub fn upload(gpu: &Arc<Gpu>, name: &str, skin: &SceneSkin, source: &SceneMesh) -> Result<Self> {
        let indices = &source.data.indices;
        let vertices = skinned_vertices(name, source, skin, 0)?;
        let mut palette = Palette::new(gpu, name)?;
        palette.update(0, &skin.joint_matrices)?;
        Ok(SkinnedMesh { mesh: GpuMesh::from_raw(gpu, name, &vertices, indices)?, palette })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertex_layout_matches_the_struct() {
        assert_eq!(PALETTE_BYTES, crate::gpu::mobile_profile::MAX_UNIFORM_BUFFER_RANGE as u64);
    }
}
