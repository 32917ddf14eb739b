//! The outline's pipelines, from the named recipes, and its pass plan for each path.
//!
//! Emulated frame, one render pass (the clear's alpha is 0):
//! 1. scene: the objects that are not selected, alpha 0;
//! 2. selected: the selected objects with the same pipeline, alpha 1;
//! 3. outline: the selected objects' extruded copies, depth test off, drawn only where alpha is
//!    0 (`COLOUR_WHERE_ALPHA_ZERO`): exactly where a stencil test `NOT_EQUAL 1` would pass.
//!
//! Reference frame: the document's. The selected objects also write stencil 1, then the same
//! copies are drawn opaque where the stencil is `NOT_EQUAL 1`. Both paths draw the unselected
//! objects first, as the document does, so the mark means "the visible surface here is
//! selected" in both.

use ash::vk;

use crate::frame::StencilMode;
use crate::pipeline::recipes::{self, COLOUR_REPLACE, COLOUR_WHERE_ALPHA_ZERO};
use crate::pipeline::{BlendState, DepthState, FixedFunction, PipelineDesc, RasterState};
use crate::render::plan::{Draws, PassPlan, PlannedPass, Push, SetRole};
use crate::technique::cartoon_shading::{shade_desc, shade_pass};
use crate::technique::extruded::extrude_desc;

/// What the scene pass draws.
pub const NOT_SELECTED: Draws = Draws::Geometry("objects not selected");
/// What the selected pass draws.
pub const SELECTED: Draws = Draws::Geometry("selected objects");
/// What the outline pass draws.
pub const SELECTED_EXTRUDED: Draws = Draws::Geometry("selected objects' extruded copies");

/// Reference only: the selected objects also write stencil 1.
pub fn selected_stencil_desc() -> PipelineDesc {
    let mut desc = shade_desc();
    desc.name = "selected (stencil)";
    desc.fixed.stencil = Some(recipes::stencil_replace(1));
    desc
}

/// Triangles of both windings, no depth test: the outline shows through what is in front of
/// the selection, as the document's does.
fn outline_fixed(blend: BlendState) -> FixedFunction {
    FixedFunction {
        topology: vk::PrimitiveTopology::TRIANGLE_LIST,
        raster: RasterState::CULL_NONE,
        depth: DepthState::OFF,
        stencil: None,
        blend,
    }
}

/// The extruded copy, blended by destination alpha: colour = outline * (1 - a) + dst * a.
pub fn outline_desc() -> PipelineDesc {
    extrude_desc("outline", outline_fixed(COLOUR_WHERE_ALPHA_ZERO))
}

/// Reference: the same copy, opaque, where the stencil is not 1.
pub fn outline_stencil_desc() -> PipelineDesc {
    let mut desc = extrude_desc("outline (stencil)", outline_fixed(COLOUR_REPLACE));
    desc.fixed.stencil = Some(recipes::stencil_not_equal(1));
    desc
}

/// The outline's passes at `stencil`.
pub fn plan(stencil: StencilMode) -> PassPlan {
    let (selected_name, selected_pipeline, outline) = match stencil {
        // The selected objects are drawn with the scene pipeline: alpha 1 is their mark.
        StencilMode::Emulated => ("selected", shade_desc(), outline_desc()),
        StencilMode::Reference => ("selected (stencil)", selected_stencil_desc(), outline_stencil_desc()),
    };
    let mut plan = PassPlan::new();
    // Unselected first (the document draws the floor before the containers).
    plan.push(shade_pass("scene", shade_desc(), NOT_SELECTED, "object transform and colour, alpha 0 (CartoonPush)"));
    plan.push(shade_pass(
        selected_name,
        selected_pipeline,
        SELECTED,
        "object transform and colour, alpha 1 (CartoonPush)",
    ));
    plan.push(
        PlannedPass::new(
            outline.name,
            outline,
            SELECTED_EXTRUDED,
            Push::PerDraw("object transform, outline colour and width (CartoonPush)"),
        )
        .with_sets(&[SetRole::Frame]),
    );
    plan
}
