//! Per-frame uniforms (`shaders/frame_uniforms.glsl`) and the descriptor set that binds them.

use std::sync::Arc;

use ash::vk;
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec4};
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::scene::camera::Light;
use crate::scene::{JointPalettes, Scene, SceneLight, MAX_LIGHTS};

/// Mirrors `FrameLight` in `shaders/frame_uniforms.glsl` (std140: four vec4s).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    /// xyz: position (w = 1) or the direction the light travels (w = 0), as `toward_light`
    /// reads it.
    pub position: Vec4,
    /// xyz: a spot light's axis (the way it shines); w: 1 / range (0: no range).
    pub direction: Vec4,
    /// rgb: colour x intensity; w unused.
    pub radiance: Vec4,
    /// x, y: KHR_lights_punctual's spot scale and offset ((0, 1) without a cone).
    pub cone: Vec4,
}

impl GpuLight {
    pub fn of(light: &SceneLight) -> Self {
        let (scale, offset) = light.cone_scale_offset();
        GpuLight {
            position: light.geometry().as_vec4(),
            direction: light.direction.extend(light.range.map_or(0.0, |r| 1.0 / r)),
            radiance: light.radiance().extend(0.0),
            cone: Vec4::new(scale, offset, 0.0, 0.0),
        }
    }
}

/// Mirrors `FrameUniforms` in `shaders/frame_uniforms.glsl` (std140: vec4s and a mat4).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct FrameUniforms {
    pub view_proj: Mat4,
    /// The primary light's geometry (the one light of the one-light techniques).
    pub light: Vec4,
    pub camera_position: Vec4,
    /// x: the ambient term; y: the number of lights; z: the primary light's index.
    pub shading: Vec4,
    pub lights: [GpuLight; MAX_LIGHTS],
}

impl FrameUniforms {
    pub fn for_scene(scene: &Scene, aspect: f32) -> Self {
        let mut lights = [GpuLight::default(); MAX_LIGHTS];
        for (slot, light) in lights.iter_mut().zip(&scene.lights) {
            *slot = GpuLight::of(light);
        }
        // The primary slot holds the primary light's geometry even in a scene without lights,
        // so passes that index the primary light (planar shadows) find the default one there.
        let primary = scene.primary_light_index().unwrap_or(0);
        lights[primary].position = scene.light().as_vec4();
        FrameUniforms {
            view_proj: scene.camera.view_projection(aspect),
            light: scene.light().as_vec4(),
            camera_position: scene.camera.eye.extend(1.0),
            shading: Vec4::new(
                scene.ambient,
                scene.lights.len().min(MAX_LIGHTS) as f32,
                scene.primary_light_index().unwrap_or(0) as f32,
                0.0,
            ),
            lights,
        }
    }

    /// Moves the primary light (light `primary` of the scene) to `light` for this frame: a
    /// technique that turns the light (the atlas's moving light) turns it for every pass.
    pub fn move_primary_light(&mut self, primary: Option<usize>, light: Light) {
        self.light = light.as_vec4();
        if let Some(slot) = self.lights.get_mut(primary.unwrap_or(0)) {
            slot.position = light.as_vec4();
        }
    }
}

/// A frame slot's set 0: its uniforms (binding 0) and its joint palettes (binding 1, every
/// skinned object's palette for this frame, `shaders/joint_palettes.glsl`).
pub struct FrameDescriptors {
    pub layout: vk::DescriptorSetLayout,
    pub set: vk::DescriptorSet,
    // Field order: the set is destroyed before the buffers it points at.
    _descriptors: DescriptorSet,
    buffer: Buffer,
    palettes: Buffer,
    /// Joints the palettes' buffer holds: sized once, for the scene the renderer draws.
    palette_joints: usize,
}

/// Bytes of one joint matrix in the palettes (std430 mat4).
const JOINT_BYTES: u64 = std::mem::size_of::<Mat4>() as u64;

impl FrameDescriptors {
    /// `palette_joints`: the joints of the frame's palettes (`JointPalettes::joints`; at least
    /// one is kept, so the binding is never empty).
    pub fn new(gpu: &Arc<Gpu>, palette_joints: usize) -> Result<Self> {
        let size = std::mem::size_of::<FrameUniforms>() as u64;
        let buffer =
            Buffer::new(gpu, "frame uniforms", size, vk::BufferUsageFlags::UNIFORM_BUFFER, MemoryLocation::CpuToGpu)?;
        // JOINTS_0 is u16, so at most 2^16 joints are ever indexed (`skinned_vertices` refuses
        // more): 4 MiB, inside any device's storage range.
        let palette_joints = palette_joints.clamp(1, 1 << 16);
        let palette_bytes = palette_joints as u64 * JOINT_BYTES;
        let palettes = Buffer::new(
            gpu,
            "joint palettes",
            palette_bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let descriptors = DescriptorSet::new(
            gpu,
            &[
                Binding::UniformBuffer {
                    buffer: buffer.raw,
                    range: size,
                    stages: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                },
                Binding::ReadOnlyStorage {
                    buffer: palettes.raw,
                    range: palette_bytes,
                    stages: vk::ShaderStageFlags::VERTEX,
                },
            ],
        )?;
        Ok(FrameDescriptors {
            layout: descriptors.layout,
            set: descriptors.set,
            _descriptors: descriptors,
            buffer,
            palettes,
            palette_joints,
        })
    }

    pub fn update(&mut self, uniforms: &FrameUniforms) -> Result<()> {
        self.buffer.write(0, bytemuck::bytes_of(uniforms))
    }

    /// Writes every skinned object's palette of `scene` where `palettes` places it. No frame in
    /// flight may read this slot.
    pub fn write_palettes(&mut self, scene: &Scene, palettes: &JointPalettes) -> Result<()> {
        if palettes.joints > self.palette_joints {
            return Err(Error::Internal(format!(
                "the scene's palettes hold {} joints; the frame's buffer was sized for {}",
                palettes.joints, self.palette_joints
            )));
        }
        for (object, first) in scene.objects.iter().zip(&palettes.first_joint) {
            if let (Some(skin), Some(first)) = (&object.skin, first) {
                self.palettes.write(*first as usize * JOINT_BYTES as usize, &skin.joint_matrices)?;
            }
        }
        Ok(())
    }
}
