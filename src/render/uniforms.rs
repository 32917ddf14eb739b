//! Per-frame uniforms (`shaders/frame_uniforms.glsl`) and the descriptor set that binds them.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};
use gpu_allocator::MemoryLocation;

use crate::error::Result;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::scene::Scene;

/// Mirrors `FrameUniforms` in `shaders/frame_uniforms.glsl` (std140: vec4s and a mat4).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct FrameUniforms {
    pub view_proj: Mat4,
    pub light: Vec4,
    pub camera_position: Vec4,
    pub shading: Vec4,
}

impl FrameUniforms {
    pub fn for_scene(scene: &Scene, aspect: f32) -> Self {
        FrameUniforms {
            view_proj: scene.camera.view_projection(aspect),
            light: scene.light.as_vec4(),
            camera_position: scene.camera.eye.extend(1.0),
            shading: Vec4::new(scene.ambient, 0.0, 0.0, 0.0),
        }
    }
}

pub struct FrameDescriptors {
    pub layout: vk::DescriptorSetLayout,
    pub set: vk::DescriptorSet,
    // Field order: the set is destroyed before the buffer it points at.
    _descriptors: DescriptorSet,
    buffer: Buffer,
}

impl FrameDescriptors {
    pub fn new(gpu: &Arc<Gpu>) -> Result<Self> {
        let size = std::mem::size_of::<FrameUniforms>() as u64;
        let buffer =
            Buffer::new(gpu, "frame uniforms", size, vk::BufferUsageFlags::UNIFORM_BUFFER, MemoryLocation::CpuToGpu)?;
        let descriptors = DescriptorSet::new(
            gpu,
            &[Binding::UniformBuffer {
                buffer: buffer.raw,
                range: size,
                stages: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            }],
        )?;
        Ok(FrameDescriptors { layout: descriptors.layout, set: descriptors.set, _descriptors: descriptors, buffer })
    }

    pub fn update(&mut self, uniforms: &FrameUniforms) -> Result<()> {
        self.buffer.write(0, bytemuck::bytes_of(uniforms))
    }
}
