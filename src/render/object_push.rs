//! The per-object push constants most pipelines share, and the plain object draw.

use glam::{Mat4, Vec4};

use super::gpu_mesh::GpuScene;
use super::recorder::FrameRecorder;
use crate::render::Pipeline;
use crate::scene::{Scene, SceneObject};

/// An object's push: its transform, its material's base colour factor (what passes that draw
/// one flat colour use; material shaders read the material) and the alpha the draw writes.
pub fn object_push(scene: &Scene, object: &SceneObject, alpha: f32) -> ObjectPush {
    ObjectPush { model: object.transform, colour: scene.base_colour(object).extend(alpha) }
}

/// Mirrors `ObjectPush` in `shaders/object_push.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ObjectPush {
    pub model: Mat4,
    /// rgb: the material's base colour factor; a: the alpha the draw writes.
    pub colour: Vec4,
}

pub const OBJECT_PUSH_BYTES: u32 = std::mem::size_of::<ObjectPush>() as u32;

/// Draws every object of `scene` with `pipeline` (bound by the caller), each with its transform,
/// its base colour and the alpha `alpha`, and its material set when `with_material`.
pub fn draw_objects(
    rec: &mut FrameRecorder,
    pipeline: &Pipeline,
    scene: &Scene,
    meshes: &GpuScene,
    alpha: f32,
    with_material: bool,
) {
    for object in &scene.objects {
        if with_material {
            rec.bind_material(pipeline, meshes.materials.set(object.material));
        }
        rec.push(pipeline, &object_push(scene, object, alpha));
        rec.draw_mesh(&meshes.meshes[object.mesh]);
    }
}
