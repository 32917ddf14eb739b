//! The per-object push constants most pipelines share, and the order objects are drawn in.

use glam::{Mat4, Vec4};

use crate::scene::model::AlphaMode;
use crate::scene::{Scene, SceneObject};

/// The order objects are drawn in: every object not blended, in scene order, then the blended
/// ones back to front (farthest centre from the eye first), as alpha blending needs. Only the
/// blended objects are gathered: a frame's passes walk this for every pass, and an allocation
/// of the whole scene's size on the render thread each time costs more than the walk.
pub fn draw_order(scene: &Scene) -> impl Iterator<Item = usize> + '_ {
    let blended = |i: usize| matches!(scene.material_of(&scene.objects[i]).alpha_mode, AlphaMode::Blend);
    let distance =
        |i: usize| scene.posed_bounds(i).map_or(0.0, |(lo, hi)| ((lo + hi) * 0.5).distance(scene.camera.eye));
    let mut back: Vec<(f32, usize)> =
        (0..scene.objects.len()).filter(|&i| blended(i)).map(|i| (distance(i), i)).collect();
    back.sort_by(|a, b| b.0.total_cmp(&a.0));
    (0..scene.objects.len()).filter(move |&i| !blended(i)).chain(back.into_iter().map(|(_, i)| i))
}

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

/// Mirrors `LightPush` in `shaders/light_push.glsl`: a per-light pass's object push, and which
/// of the frame's lights it shades.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LightPush {
    pub object: ObjectPush,
    /// x: the light's index in the frame's lights.
    pub light: [u32; 4],
}

pub const LIGHT_PUSH_BYTES: u32 = std::mem::size_of::<LightPush>() as u32;
