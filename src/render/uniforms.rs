//! Per-frame uniforms (`shaders/frame_uniforms.glsl`) and the descriptor set that binds them.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec4};
use gpu_allocator::MemoryLocation;

use crate::error::{Result, VkContext};
use crate::gpu::memory::{as_bytes, Buffer};
use crate::gpu::Gpu;
use crate::scene::Scene;

/// Mirrors `FrameUniforms` in `shaders/frame_uniforms.glsl` (std140: vec4s and a mat4).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
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
    gpu: Arc<Gpu>,
    pub layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    pub set: vk::DescriptorSet,
    buffer: Buffer,
}

impl FrameDescriptors {
    pub fn new(gpu: &Arc<Gpu>) -> Result<Self> {
        let device = gpu.raw();
        let bindings = [vk::DescriptorSetLayoutBinding::default()
            .binding(0)
            .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT)];
        let layout = unsafe {
            device.create_descriptor_set_layout(&vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings), None)
        }
        .vk("vkCreateDescriptorSetLayout")?;
        let sizes = [vk::DescriptorPoolSize { ty: vk::DescriptorType::UNIFORM_BUFFER, descriptor_count: 1 }];
        let pool = unsafe {
            device.create_descriptor_pool(&vk::DescriptorPoolCreateInfo::default().max_sets(1).pool_sizes(&sizes), None)
        }
        .vk("vkCreateDescriptorPool")?;
        let layouts = [layout];
        let set = unsafe {
            device.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default().descriptor_pool(pool).set_layouts(&layouts),
            )
        }
        .vk("vkAllocateDescriptorSets")?[0];
        let size = std::mem::size_of::<FrameUniforms>() as u64;
        let buffer =
            Buffer::new(gpu, "frame uniforms", size, vk::BufferUsageFlags::UNIFORM_BUFFER, MemoryLocation::CpuToGpu)?;
        let buffer_info = [vk::DescriptorBufferInfo { buffer: buffer.raw, offset: 0, range: size }];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(0)
            .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
            .buffer_info(&buffer_info);
        unsafe { device.update_descriptor_sets(&[write], &[]) };
        Ok(FrameDescriptors { gpu: gpu.clone(), layout, pool, set, buffer })
    }

    pub fn update(&mut self, uniforms: &FrameUniforms) -> Result<()> {
        self.buffer.write(0, as_bytes(std::slice::from_ref(uniforms)))
    }
}

impl Drop for FrameDescriptors {
    fn drop(&mut self) {
        let device = self.gpu.raw();
        unsafe {
            device.destroy_descriptor_pool(self.pool, None);
            device.destroy_descriptor_set_layout(self.layout, None);
        }
    }
}
