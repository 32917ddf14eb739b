//! Fixed-function state as plain, named data. The renderer builds pipelines from these values
//! and `nostencil passes` prints them, so what a port copies is what actually runs.

use ash::vk;

/// One blend equation: `result = op(src * src_factor, dst * dst_factor)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BlendEquation {
    pub op: vk::BlendOp,
    pub src: vk::BlendFactor,
    pub dst: vk::BlendFactor,
}

impl BlendEquation {
    pub const fn new(op: vk::BlendOp, src: vk::BlendFactor, dst: vk::BlendFactor) -> Self {
        BlendEquation { op, src, dst }
    }
    /// What "blending off" computes: the fragment replaces the pixel.
    pub const REPLACE: BlendEquation =
        BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ONE, vk::BlendFactor::ZERO);
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BlendState {
    /// `None` for both means blending disabled (the fragment replaces the pixel).
    pub colour: Option<BlendEquation>,
    pub alpha: Option<BlendEquation>,
    pub write_mask: vk::ColorComponentFlags,
}

impl BlendState {
    pub const OPAQUE: BlendState = BlendState { colour: None, alpha: None, write_mask: vk::ColorComponentFlags::RGBA };

    pub fn enabled(&self) -> bool {
        self.colour.is_some() || self.alpha.is_some()
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DepthState {
    /// `None`: depth test off.
    pub compare: Option<vk::CompareOp>,
    pub write: bool,
}

impl DepthState {
    pub const WRITE_LESS: DepthState = DepthState { compare: Some(vk::CompareOp::LESS), write: true };
    pub const OFF: DepthState = DepthState { compare: None, write: false };
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthBias {
    pub constant: f32,
    pub slope: f32,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RasterState {
    pub cull: vk::CullModeFlags,
    /// Front faces are counter-clockwise in framebuffer space (after the Y flip in the projection).
    pub front_face: vk::FrontFace,
    pub depth_bias: Option<DepthBias>,
}

impl RasterState {
    pub const CULL_BACK: RasterState =
        RasterState { cull: vk::CullModeFlags::BACK, front_face: vk::FrontFace::COUNTER_CLOCKWISE, depth_bias: None };
    pub const CULL_FRONT: RasterState = RasterState { cull: vk::CullModeFlags::FRONT, ..RasterState::CULL_BACK };
    pub const CULL_NONE: RasterState = RasterState { cull: vk::CullModeFlags::NONE, ..RasterState::CULL_BACK };
}

/// Stencil state: only the real-stencil reference path may use it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StencilState {
    pub front: StencilFace,
    pub back: StencilFace,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StencilFace {
    pub compare: vk::CompareOp,
    pub reference: u32,
    pub compare_mask: u32,
    pub write_mask: u32,
    pub fail: vk::StencilOp,
    pub pass: vk::StencilOp,
    pub depth_fail: vk::StencilOp,
}

impl StencilFace {
    pub fn to_vk(self) -> vk::StencilOpState {
        vk::StencilOpState {
            fail_op: self.fail,
            pass_op: self.pass,
            depth_fail_op: self.depth_fail,
            compare_op: self.compare,
            compare_mask: self.compare_mask,
            write_mask: self.write_mask,
            reference: self.reference,
        }
    }
}

/// Everything fixed-function about one pass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedFunction {
    pub topology: vk::PrimitiveTopology,
    pub raster: RasterState,
    pub depth: DepthState,
    pub stencil: Option<StencilState>,
    pub blend: BlendState,
}

impl FixedFunction {
    /// Opaque lit geometry: back faces culled, depth test and write.
    pub const OPAQUE: FixedFunction = FixedFunction {
        topology: vk::PrimitiveTopology::TRIANGLE_LIST,
        raster: RasterState::CULL_BACK,
        depth: DepthState::WRITE_LESS,
        stencil: None,
        blend: BlendState::OPAQUE,
    };

    /// A full-screen triangle: no culling, no depth.
    pub const FULLSCREEN: FixedFunction = FixedFunction {
        topology: vk::PrimitiveTopology::TRIANGLE_LIST,
        raster: RasterState::CULL_NONE,
        depth: DepthState::OFF,
        stencil: None,
        blend: BlendState::OPAQUE,
    };
}
