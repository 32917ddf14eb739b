//! The outline's pipelines, from the named recipes, and its pass plan for each path.
//!
//! Emulated frame, one render pass (the clear's alpha is 0):
//! 1. scene: the objects that are not selected, alpha 0;
//! 2. selected: the selected objects with the same pipeline, alpha 1;
//! 3. outline: the selected objects' copies (extruded along their normals, or scaled up about
//!    their centres with `--outline-method scale`), depth test off, drawn only where alpha is
//!    0 (`COLOUR_WHERE_ALPHA_ZERO`): exactly where a stencil test `NOT_EQUAL 1` would pass.
//!
//! With `--outline-blur R` the outline pass is replaced: the mask and two blur passes run
//! offscreen first, and the blurred outline is blended over the frame last (see `blur`).
//!
//! Reference frame: the document's. The selected objects also write stencil 1, then the same
//! copies are drawn opaque where the stencil is `NOT_EQUAL 1`. Both paths draw the unselected
//! objects first, as the document does, so the mark means "the visible surface here is
//! selected" in both.

use glam::Vec4;

use super::blur;
use super::copies::{copy_desc, outline_fixed};
use super::kinds::{OutlineDraw, OutlineKinds};
use crate::frame::StencilMode;
use crate::pipeline::recipes::{self, COLOUR_REPLACE, COLOUR_WHERE_ALPHA_ZERO};
use crate::pipeline::PipelineDesc;
use crate::render::plan::{PassPlan, PlannedPass, SetRole};
use crate::technique::cartoon_shading::{shade_desc, shade_pass};
use crate::technique::options::{CartoonOptions, OutlineMethod};

/// Reference only: the selected objects also write stencil 1.
pub fn selected_stencil_desc() -> PipelineDesc {
    let mut desc = shade_desc();
    desc.name = "selected (stencil)";
    desc.fixed.stencil = Some(recipes::stencil_replace(1));
    desc
}

/// The copy, blended by destination alpha: colour = outline * (1 - a) + dst * a.
pub fn outline_desc(method: OutlineMethod) -> PipelineDesc {
    copy_desc(method, ["outline", "outline (scaled)"], outline_fixed(COLOUR_WHERE_ALPHA_ZERO))
}

/// Reference: the same copy, opaque, where the stencil is not 1.
pub fn outline_stencil_desc(method: OutlineMethod) -> PipelineDesc {
    let names = ["outline (stencil)", "outline (scaled, stencil)"];
    let mut desc = copy_desc(method, names, outline_fixed(COLOUR_REPLACE));
    desc.fixed.stencil = Some(recipes::stencil_not_equal(1));
    desc
}

/// The outline's linear colour, as its shaders write it (the option is sRGB bytes).
pub fn linear_colour(cartoon: &CartoonOptions) -> Vec4 {
    let [r, g, b] = cartoon.outline_colour.map(crate::frame::srgb::decode);
    Vec4::new(r, g, b, 1.0)
}

/// The outline's passes at `stencil` with the copies, colour and blur of `cartoon`.
pub fn plan(stencil: StencilMode, cartoon: &CartoonOptions) -> PassPlan<OutlineKinds> {
    let method = cartoon.outline_method;
    let (selected_name, selected_pipeline, outline) = match stencil {
        // The selected objects are drawn with the scene pipeline: alpha 1 is their mark.
        StencilMode::Emulated => ("selected", shade_desc(), outline_desc(method)),
        StencilMode::Reference => ("selected (stencil)", selected_stencil_desc(), outline_stencil_desc(method)),
    };
    let push = match method {
        OutlineMethod::Extrude => "object transform, outline colour and width (CartoonPush)",
        OutlineMethod::Scale => "object transform, outline colour, scale and centre (CartoonPush)",
    };
    let mut plan = PassPlan::new();
    if cartoon.outline_blur > 0 {
        // Offscreen: they run before the frame's render pass.
        plan.extend(blur::offscreen_passes(stencil, method, cartoon.outline_blur));
    }
    // Unselected first (the document draws the floor before the containers).
    let scene = shade_pass(
        "scene",
        shade_desc(),
        OutlineDraw::NotSelected,
        "object transform and colour, alpha 0 (CartoonPush)",
    );
    plan.push(scene);
    plan.push(shade_pass(
        selected_name,
        selected_pipeline,
        OutlineDraw::Selected,
        "object transform and colour, alpha 1 (CartoonPush)",
    ));
    if cartoon.outline_blur > 0 {
        plan.push(blur::apply_pass(linear_colour(cartoon)));
        return plan;
    }
    plan.push(PlannedPass::own(outline.name, outline, OutlineDraw::Copies(method), push).with_sets(&[SetRole::Frame]));
    plan
}
