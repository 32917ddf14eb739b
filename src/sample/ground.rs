//! What a sample drawing on the ground needs beyond the base (`examples/planar_shadows.rs`):
//! the receiving plane the engine finds and which objects lie in it, pipelines with a depth
//! bias (what lies flat on the ground drawn over it), and draws of the scene's objects each
//! with a push of the sample's own.

use ash::vk;
use glam::Vec4;

use super::{PipelineParts, SampleBase};
use crate::error::Result;
use crate::render::object_push::{draw_order, object_push};
use crate::scene::SceneObject;

/// The ground every planar shadow falls on, as the engine finds it.
pub struct Ground {
    /// The plane `(n, d)`: `n.x + d = 0`, `n` unit, pointing to the casters' side.
    pub plane: Vec4,
    /// Per object (by index in `scene.objects`): whether it lies in the plane, a receiver.
    /// Every other object casts.
    pub receivers: Vec<bool>,
}

impl SampleBase {
    /// The scene's ground: the lowest flat, horizontal, non-casting object's plane, and every
    /// such object in it (the engine's `receiver_plane`). A scene without one is refused, and
    /// so is a primary light that casts nothing onto it (parallel to it, or below it).
    pub fn ground(&self) -> Result<Ground> {
        let found = crate::technique::planar::receiver_plane(&self.scene, None)?;
        let light = self.scene.light();
        found.plane.check_light(&light)?;
        if !found.plane.reached_by(&light) {
            return Err(crate::error::Error::InvalidInput(format!(
                "scene '{}': the light is below the ground, which receives no shadow",
                self.scene.name
            )));
        }
        Ok(Ground { plane: found.plane.as_vec4(), receivers: found.receivers })
    }

    /// [`SampleBase::pipeline`] with a depth bias: depth moved by `constant` units of the depth
    /// format's resolution plus `slope` times the triangle's depth slope (negative: towards
    /// the camera).
    pub fn pipeline_with_depth_bias(&self, parts: &PipelineParts, constant: f32, slope: f32) -> Result<vk::Pipeline> {
        self.pipeline_biased(self.layout, parts, Some((constant, slope)))
    }

    /// The push [`SampleBase::draw_objects`] gives `object`: its transform, its material's base
    /// colour and `alpha` (`shaders/object_push.glsl`).
    pub fn object_push(&self, object: &SceneObject, alpha: f32) -> Vec<u8> {
        bytemuck::bytes_of(&object_push(&self.scene, object, alpha)).to_vec()
    }

    /// Draws, in the engine's order and with the bound pipeline (a [`super::VertexInput::Scene`]
    /// one), every object `push` gives a push (by its index and itself; `None`: not drawn),
    /// each with its material (set 1).
    pub fn draw_objects_with(&self, cmd: vk::CommandBuffer, push: impl Fn(usize, &SceneObject) -> Option<Vec<u8>>) {
        self.bind_frame_uniforms(cmd);
        let device = self.device();
        for index in draw_order(&self.scene) {
            let object = &self.scene.objects[index];
            let Some(mesh) = self.gpu_scene.meshes.get(object.mesh) else { continue };
            let Some(bytes) = push(index, object) else { continue };
            let material = self.gpu_scene.materials.set(object.material);
            self.push(cmd, &bytes);
            let (vertices, vertex_offset) = mesh.vertices_in(0);
            // SAFETY: `cmd` is recording inside a render pass with a scene pipeline bound; every
            // buffer and set bound is a field of the base, alive until it is dropped.
            unsafe {
                device.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, self.layout, 1, &[material], &[]);
                device.cmd_bind_vertex_buffers(cmd, 0, &[vertices.raw], &[0]);
                device.cmd_bind_index_buffer(cmd, mesh.indices().raw, 0, vk::IndexType::UINT32);
                device.cmd_draw_indexed(cmd, mesh.index_count, 1, mesh.first_index, vertex_offset, 0);
            }
        }
    }
}
