//! What every planar projected shadow pass shares, the seed's one shadow and the per-light
//! loop's flags alike: the push constants, the plan's kinds and draws, and the pipeline that
//! flattens casters onto the plane.

use ash::vk;
use glam::{Mat4, Vec4};

use super::shared::SHADOW_BIAS;
use crate::pipeline::{BlendState, DepthState, FixedFunction, PipelineDesc, RasterState, StencilState, VertexLayout};
use crate::render::plan::{DrawKind, NoOwn, PassKinds};
use crate::shaders;

/// Mirrors `PlanarPush` in `shaders/planar_push.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PlanarPush {
    pub model: Mat4,
    pub colour: Vec4,
    /// The receiving plane (n, d): n.x + d = 0.
    pub plane: Vec4,
    /// x: the index in the frame's lights of the light the shadow is cast from.
    pub light: [u32; 4],
}

pub const PLANAR_PUSH_BYTES: u32 = std::mem::size_of::<PlanarPush>() as u32;
// The shaders' push block is 112 bytes, within the profile's 128.
const _: () = assert!(PLANAR_PUSH_BYTES == 112);

/// The kinds of the planar plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PlanarKinds;

impl PassKinds for PlanarKinds {
    type Draw = PlanarDraw;
    type Set = NoOwn;
    type Target = NoOwn;
}

/// What the planar renderer draws itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PlanarDraw {
    /// Every object, receivers writing the shadow factor into alpha (or marking the stencil).
    Scene,
    /// The casters flattened onto the plane, or (`lod`) their simplified meshes, along `light`
    /// (the additive loop's light; none: the seed's one shadow, from the primary light).
    ProjectedCasters { lod: bool, light: Option<u8> },
    /// The additive loop's first pass: opaque objects in ambient light, alpha 1 (the
    /// reference clears its stencil to 0 first).
    Ambient,
    /// Light `light` added to the opaque objects: on receivers only where its flag is unset
    /// when it is `shadowed` (the reference clears its stencil again after it).
    Shading { light: u8, shadowed: bool },
    /// Blended objects after the loop, lit by every light and unshadowed.
    Transparent,
}

impl DrawKind for PlanarDraw {
    fn describe(self) -> &'static str {
        match self {
            PlanarDraw::Scene => "objects",
            PlanarDraw::ProjectedCasters { lod: false, .. } => "casters flattened onto the plane",
            PlanarDraw::ProjectedCasters { lod: true, .. } => {
                "simplified casters (meshoptimizer) flattened onto the plane"
            }
            PlanarDraw::Ambient => "opaque objects, ambient light",
            PlanarDraw::Shading { shadowed: true, .. } => "opaque objects, the light added where unshadowed",
            PlanarDraw::Shading { shadowed: false, .. } => "opaque objects, the light added",
            PlanarDraw::Transparent => "blended objects, every light",
        }
    }
}

/// A flattened-caster pipeline with `blend` and `stencil`.
pub fn flattened_desc(
    name: &'static str,
    skinned: bool,
    blend: BlendState,
    stencil: Option<StencilState>,
) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: if skinned { shaders::PLANAR_SHADOW_SKINNED_VERT } else { shaders::PLANAR_SHADOW_VERT },
        fragment_shader: shaders::OBJECT_COLOUR_FRAG,
        vertex_layout: if skinned { VertexLayout::SKINNED_SCENE } else { VertexLayout::SCENE },
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            // Flattened, front and back faces both land on the plane: both are drawn, which is
            // exactly the overlap the blend (or the stencil) must not count twice.
            raster: RasterState { depth_bias: Some(SHADOW_BIAS), ..RasterState::CULL_NONE },
            depth: DepthState { compare: Some(vk::CompareOp::LESS_OR_EQUAL), write: false },
            stencil,
            blend,
        },
        push_constant_bytes: PLANAR_PUSH_BYTES,
    }
}
