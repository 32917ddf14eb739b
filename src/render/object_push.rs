//! The per-object push constants most pipelines share, and the plain object draw.

use glam::{Mat4, Vec4};

use super::gpu_mesh::GpuScene;
use super::recorder::FrameRecorder;
use crate::render::Pipeline;
use crate::scene::Scene;

/// Mirrors `ObjectPush` in `shaders/object_push.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ObjectPush {
    pub model: Mat4,
    /// rgb: albedo; a: the alpha the draw writes.
    pub colour: Vec4,
}

pub const OBJECT_PUSH_BYTES: u32 = std::mem::size_of::<ObjectPush>() as u32;

/// Draws every object of `scene` with `pipeline` (bound by the caller), each with its transform
/// and colour and the alpha `alpha`.
pub fn draw_objects(rec: &mut FrameRecorder, pipeline: &Pipeline, scene: &Scene, meshes: &GpuScene, alpha: f32) {
    for object in &scene.objects {
        let push = ObjectPush { model: object.transform, colour: object.colour.extend(alpha) };
        rec.push(pipeline, &push);
        rec.draw_mesh(&meshes.meshes[object.mesh]);
    }
}
