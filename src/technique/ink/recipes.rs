//! The ink techniques' pipelines and their pass plan for each `--silhouette` method.
//!
//! Every frame, one render pass: the scene (Lambert, or N.L through the toon ramp; with the
//! rim ramp at N.V for `shader`), then the ink:
//! - `edges`: one pass per edge class (silhouette, crease, boundary), each one draw of the
//!   screen-space quads the CPU built this frame;
//! - `shader`: nothing more, the rim is the ink;
//! - `hull`: the inverted hull, each object's extruded copy with its front faces culled;
//! - `extrusion`: no scene pass of its own: one pass draws, object by object, its extruded
//!   copy with the depth test and write off, then the object (so it binds both pipelines);
//! - `alpha-test`: the objects again, depth EQUAL, N.V per pixel as alpha, kept (as ink) where
//!   it is at most the reference value.

use ash::vk;

use crate::pipeline::recipes::COLOUR_REPLACE;
use crate::pipeline::{DepthState, FixedFunction, PipelineDesc, RasterState, VertexAttribute, VertexLayout};
use crate::render::plan::{DrawKind, Label, NoOwn, PassKinds, PassPlan, PlannedPass, SetRole};
use crate::shaders;
use crate::technique::cartoon_shading::{cartoon_desc, shade_desc, shade_pass, WithRamps};
use crate::technique::extruded::extrude_desc;
use crate::technique::options::SilhouetteMethod;

/// position (vec3) a, b, c + corner (vec2): `InkVertex`.
pub const INK_LAYOUT: VertexLayout = VertexLayout {
    attributes: &[VertexAttribute::Vec3, VertexAttribute::Vec3, VertexAttribute::Vec3, VertexAttribute::Vec2],
};

/// The kinds of the ink plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct InkKinds;

impl PassKinds for InkKinds {
    type Draw = InkDraw;
    type Set = InkSet;
    type Target = NoOwn;
}

/// What the ink renderer draws itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InkDraw {
    /// Every object, shaded (Lambert, toon ramp, rim).
    Scene,
    /// One edge class's screen-space quads (an index into the edge classes: silhouette, crease, boundary).
    EdgeQuads(usize),
    /// Every object's extruded copy (the inverted hull).
    Hull,
    /// Per object: its extruded copy with depth off, then the object (the seed's extrusion).
    CopyThenObject,
    /// Every object again, its ink kept where N.V is at most the reference (alpha test).
    AlphaTest,
}

impl DrawKind for InkDraw {
    fn describe(self) -> &'static str {
        match self {
            InkDraw::Scene => "objects",
            InkDraw::EdgeQuads(class) => EDGE_CLASSES.get(class).map_or("edge quads", |c| c.draws),
            InkDraw::Hull => "extruded copies",
            InkDraw::CopyThenObject => "per object: its extruded copy, then the object",
            InkDraw::AlphaTest => "objects",
        }
    }
}

/// The ink plan's descriptor sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum InkSet {
    Ramps,
}

impl Label for InkSet {
    fn label(self) -> &'static str {
        match self {
            InkSet::Ramps => "toon ramps",
        }
    }
}

impl WithRamps for InkSet {
    const RAMPS: Self = InkSet::Ramps;
}

/// An edge class's pass: its name, what it draws, and whether its lines grow to one side
/// (silhouettes grow away from the model; creases and boundaries are centred on the edge).
pub struct EdgeClassPass {
    pub name: &'static str,
    pub draws: &'static str,
    pub one_sided: bool,
}

/// The edge classes in the order their passes run (and `InkQuads` lists them).
pub const EDGE_CLASSES: [EdgeClassPass; 3] = [
    EdgeClassPass { name: "ink silhouette", draws: "silhouette edge quads", one_sided: true },
    EdgeClassPass { name: "ink crease", draws: "crease edge quads", one_sided: false },
    EdgeClassPass { name: "ink boundary", draws: "boundary edge quads", one_sided: false },
];

/// Ink quads: depth tested (LESS_OR_EQUAL, pulled towards the eye in the vertex shader), no
/// depth write, colour only.
pub fn ink_desc() -> PipelineDesc {
    cartoon_desc(
        "ink lines",
        shaders::CARTOON_INK_VERT,
        shaders::CARTOON_COLOUR_FRAG,
        INK_LAYOUT,
        FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster: RasterState::CULL_NONE,
            depth: DepthState { compare: Some(vk::CompareOp::LESS_OR_EQUAL), write: false },
            stencil: None,
            blend: COLOUR_REPLACE,
        },
    )
}

/// Inverted hull: the extruded copy with its front faces culled, depth tested and written, so
/// only the rim around the model (and at its folds) shows.
pub fn hull_desc() -> PipelineDesc {
    extrude_desc("inverted hull", FixedFunction { raster: RasterState::CULL_FRONT, ..FixedFunction::OPAQUE })
}

/// The name of the `extrusion` pass (copy then object, per object).
pub const EXTRUSION: &str = "extruded copy, then object";

/// The seed's extruded copy: depth test and write off (so nothing drawn before hides it, and
/// it hides nothing drawn after), back faces culled, ink in RGB.
pub fn extrusion_desc() -> PipelineDesc {
    extrude_desc(
        "extruded copy (depth off)",
        FixedFunction { depth: DepthState::OFF, blend: COLOUR_REPLACE, ..FixedFunction::OPAQUE },
    )
}

/// The name of the `alpha-test` ink pass.
pub const ALPHA_TEST: &str = "alpha-test ink";

/// Dietrich's alpha test: the objects again over the scene pass (the same vertex shader,
/// `invariant gl_Position`, so depth EQUAL finds exactly their visible pixels), N.V as alpha,
/// kept where it is at most the reference (LESS_EQUAL); ink in RGB, alpha untouched.
pub fn alpha_test_desc() -> PipelineDesc {
    cartoon_desc(
        "alpha-test ink",
        shaders::CARTOON_SHADE_VERT,
        shaders::CARTOON_ALPHA_TEST_FRAG,
        VertexLayout::SCENE,
        FixedFunction {
            depth: DepthState { compare: Some(vk::CompareOp::EQUAL), write: false },
            blend: COLOUR_REPLACE,
            ..FixedFunction::OPAQUE
        },
    )
}

/// The passes of a frame inked by `method`.
pub fn plan(method: SilhouetteMethod) -> PassPlan<InkKinds> {
    let mut plan = PassPlan::new();
    const SCENE_PUSH: &str = "object transform and colour, alpha 1; toon and rim switches (CartoonPush)";
    if method == SilhouetteMethod::Extrusion {
        let push = "copy: object transform, ink colour, line width; object: as the scene pass (CartoonPush)";
        let pass = shade_pass(EXTRUSION, shade_desc(), InkDraw::CopyThenObject, push);
        plan.push(pass.or_pipeline(extrusion_desc()));
        return plan;
    }
    plan.push(shade_pass("scene", shade_desc(), InkDraw::Scene, SCENE_PUSH));
    match method {
        SilhouetteMethod::Edges => {
            plan.extend(EDGE_CLASSES.iter().enumerate().map(|(index, class)| {
                let push = "ink colour, line width, one-sided, depth pull (CartoonPush)";
                PlannedPass::own(class.name, ink_desc(), InkDraw::EdgeQuads(index), push).with_sets(&[SetRole::Frame])
            }));
        }
        SilhouetteMethod::Shader | SilhouetteMethod::Extrusion => {}
        SilhouetteMethod::Hull => {
            plan.push(
                PlannedPass::own(
                    "inverted hull",
                    hull_desc(),
                    InkDraw::Hull,
                    "object transform, ink colour and line width (CartoonPush)",
                )
                .with_sets(&[SetRole::Frame]),
            );
        }
        SilhouetteMethod::AlphaTest => {
            plan.push(
                PlannedPass::own(
                    ALPHA_TEST,
                    alpha_test_desc(),
                    InkDraw::AlphaTest,
                    "object transform, ink colour, alpha reference (CartoonPush)",
                )
                .with_sets(&[SetRole::Frame]),
            );
        }
    }
    plan
}
