//! What a graphics pipeline is made of, as plain data: shaders by file name, an interleaved
//! vertex layout, and the fixed-function state of `state.rs`. `render::Pipeline` turns a
//! description into the Vulkan object.

use crate::shaders::Shader;
use ash::vk;

use super::state::FixedFunction;

/// One vertex attribute as the shader declares it. Each names its Vulkan format and its size
/// together, so a layout cannot hold a format whose size is unknown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VertexAttribute {
    /// `float`.
    F32,
    /// `vec2`.
    Vec2,
    /// `vec3`.
    Vec3,
    /// `vec4`.
    Vec4,
    /// `uvec4` read from four u16 (glTF JOINTS_0).
    U16x4,
}

impl VertexAttribute {
    pub const fn format(self) -> vk::Format {
        match self {
            VertexAttribute::F32 => vk::Format::R32_SFLOAT,
            VertexAttribute::Vec2 => vk::Format::R32G32_SFLOAT,
            VertexAttribute::Vec3 => vk::Format::R32G32B32_SFLOAT,
            VertexAttribute::Vec4 => vk::Format::R32G32B32A32_SFLOAT,
            VertexAttribute::U16x4 => vk::Format::R16G16B16A16_UINT,
        }
    }

    /// Bytes the attribute takes in an interleaved vertex.
    pub const fn size(self) -> u32 {
        match self {
            VertexAttribute::F32 => 4,
            VertexAttribute::Vec2 | VertexAttribute::U16x4 => 8,
            VertexAttribute::Vec3 => 12,
            VertexAttribute::Vec4 => 16,
        }
    }
}

/// One interleaved vertex buffer with these attributes at locations 0, 1, ...
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VertexLayout {
    pub attributes: &'static [VertexAttribute],
}

const SCENE_ATTRIBUTES: [VertexAttribute; 5] =
    [VertexAttribute::Vec3, VertexAttribute::Vec3, VertexAttribute::Vec2, VertexAttribute::Vec2, VertexAttribute::Vec4];
const POSITION4_ATTRIBUTES: [VertexAttribute; 1] = [VertexAttribute::Vec4];
const ATLAS_ATTRIBUTES: [VertexAttribute; 6] = [
    VertexAttribute::Vec3,
    VertexAttribute::Vec3,
    VertexAttribute::Vec2,
    VertexAttribute::Vec2,
    VertexAttribute::Vec2,
    VertexAttribute::Vec4,
];

/// `base`'s attributes, then JOINTS_0 and WEIGHTS_0 (`M` is `N + 2`).
const fn with_skin<const N: usize, const M: usize>(base: [VertexAttribute; N]) -> [VertexAttribute; M] {
    let mut out = [VertexAttribute::F32; M];
    let mut i = 0;
    while i < N {
        out[i] = base[i];
        i += 1;
    }
    out[N] = VertexAttribute::U16x4;
    out[N + 1] = VertexAttribute::Vec4;
    out
}

impl VertexLayout {
    /// No vertex buffer: the shader makes its vertices from gl_VertexIndex.
    pub const NONE: VertexLayout = VertexLayout { attributes: &[] };
    /// position (vec3) + normal (vec3).
    pub const POSITION_NORMAL: VertexLayout =
        VertexLayout { attributes: &[VertexAttribute::Vec3, VertexAttribute::Vec3] };
    /// What scene meshes hold (`render::GpuScene`): position, normal, UV0, UV1 (vec2 each) and
    /// COLOR_0 (vec4, white when the mesh has none). Pipelines that read only some of them
    /// declare the whole layout all the same: the buffers are shared.
    pub const SCENE: VertexLayout = VertexLayout { attributes: &SCENE_ATTRIBUTES };
    /// Homogeneous position (vec4): w = 0 puts a vertex at infinity (shadow-volume extrusion).
    pub const POSITION4: VertexLayout = VertexLayout { attributes: &POSITION4_ATTRIBUTES };
    /// Clip-space position (vec4) given directly, for screen-space test geometry.
    #[cfg(test)]
    pub const CLIP4: VertexLayout = VertexLayout { attributes: &[VertexAttribute::Vec4] };
    /// The shadow techniques' vertex: position, normal (vec3), atlas UV, UV0, UV1 (vec2) and
    /// COLOR_0 (vec4).
    pub const ATLAS: VertexLayout = VertexLayout { attributes: &ATLAS_ATTRIBUTES };

    /// `SCENE`, then JOINTS_0 (uvec4 read from four u16) and WEIGHTS_0 (vec4): a skinned
    /// object's bind pose, which its vertex stage skins (80 bytes).
    pub const SKINNED_SCENE: VertexLayout = VertexLayout { attributes: &with_skin::<5, 7>(SCENE_ATTRIBUTES) };
    /// `POSITION4`, then JOINTS_0 and WEIGHTS_0: a skinned caster's doubled volume vertices.
    pub const SKINNED_POSITION4: VertexLayout = VertexLayout { attributes: &with_skin::<1, 3>(POSITION4_ATTRIBUTES) };
    /// `ATLAS`, then JOINTS_0 and WEIGHTS_0.
    pub const SKINNED_ATLAS: VertexLayout = VertexLayout { attributes: &with_skin::<6, 8>(ATLAS_ATTRIBUTES) };

    /// The layout a skinned twin of a pipeline over this one reads: the same attributes, then
    /// JOINTS_0 and WEIGHTS_0 (`None` for a layout no twin is made for).
    pub fn skinned(&self) -> Option<VertexLayout> {
        match *self {
            VertexLayout::SCENE => Some(VertexLayout::SKINNED_SCENE),
            VertexLayout::POSITION4 => Some(VertexLayout::SKINNED_POSITION4),
            VertexLayout::ATLAS => Some(VertexLayout::SKINNED_ATLAS),
            _ => None,
        }
    }

    pub fn stride(&self) -> u32 {
        self.attributes.iter().map(|a| a.size()).sum()
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct PipelineDesc {
    /// The pass name this pipeline draws (shown in profiles and the `passes` table).
    pub name: &'static str,
    pub vertex_shader: Shader,
    pub fragment_shader: Shader,
    pub vertex_layout: VertexLayout,
    pub fixed: FixedFunction,
    pub push_constant_bytes: u32,
}

impl PipelineDesc {
    /// The same pipeline for skinned vertices: the vertex shader's skinned twin (`build.rs`
    /// compiles one for every vertex shader marked `// twin: skinned`) over the layout with
    /// JOINTS_0 and WEIGHTS_0 added. `None` when the shader has no twin.
    pub fn skinned_twin(&self) -> Option<PipelineDesc> {
        let vertex_shader = self.vertex_shader.skinned_twin()?;
        let vertex_layout = self.vertex_layout.skinned()?;
        Some(PipelineDesc { vertex_shader, vertex_layout, ..self.clone() })
    }
}

#[cfg(test)]
mod tests {
    use super::{VertexAttribute, VertexLayout};

    #[test]
    fn a_skinned_layout_is_its_base_then_joints_and_weights() {
        for (base, skinned) in [
            (VertexLayout::SCENE, VertexLayout::SKINNED_SCENE),
            (VertexLayout::POSITION4, VertexLayout::SKINNED_POSITION4),
            (VertexLayout::ATLAS, VertexLayout::SKINNED_ATLAS),
        ] {
            assert_eq!(base.skinned(), Some(skinned));
            assert_eq!(&skinned.attributes[..base.attributes.len()], base.attributes);
            assert_eq!(&skinned.attributes[base.attributes.len()..], &[VertexAttribute::U16x4, VertexAttribute::Vec4]);
        }
        assert_eq!(VertexLayout::POSITION_NORMAL.skinned(), None);
    }
}
