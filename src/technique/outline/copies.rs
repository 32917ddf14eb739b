//! The outline copy's pipelines: the selected objects extruded along their normals or scaled
//! about their centres, in any fixed-function state (the frame's outline, the blur's mask).

use ash::vk;

use crate::pipeline::{BlendState, DepthState, FixedFunction, PipelineDesc, RasterState, VertexLayout};
use crate::shaders;
use crate::technique::cartoon_shading::cartoon_desc;
use crate::technique::extruded::extrude_desc;
use crate::technique::options::OutlineMethod;

/// Triangles of both windings, no depth test: the outline shows through what is in front of
/// the selection, as the document's does.
pub fn outline_fixed(blend: BlendState) -> FixedFunction {
    FixedFunction {
        topology: vk::PrimitiveTopology::TRIANGLE_LIST,
        raster: RasterState::CULL_NONE,
        depth: DepthState::OFF,
        stencil: None,
        blend,
    }
}

/// The outline copy of `method` under `fixed`, called `names[0]` extruded, `names[1]` scaled.
pub fn copy_desc(method: OutlineMethod, names: [&'static str; 2], fixed: FixedFunction) -> PipelineDesc {
    match method {
        OutlineMethod::Extrude => extrude_desc(names[0], fixed),
        OutlineMethod::Scale => cartoon_desc(
            names[1],
            shaders::OUTLINE_SCALE_VERT,
            shaders::CARTOON_COLOUR_FRAG,
            VertexLayout::POSITION_NORMAL,
            fixed,
        ),
    }
}
