//! The outline's pass kinds: what its renderer draws itself, its descriptor sets and its
//! offscreen render passes, shared by the plan (`recipes`, `blur`) and the renderer.

use crate::render::plan::{DrawKind, Label, PassKinds};
use crate::technique::cartoon_shading::WithRamps;
use crate::technique::options::OutlineMethod;

/// The kinds of the outline's plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct OutlineKinds;

impl PassKinds for OutlineKinds {
    type Draw = OutlineDraw;
    type Set = OutlineSet;
    type Target = OutlineTarget;
}

/// What the outline renderer draws itself.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OutlineDraw {
    /// The objects that are not selected, alpha 0.
    NotSelected,
    /// The selected objects, alpha 1: their mark.
    Selected,
    /// The selected objects' copies, extruded or scaled up.
    Copies(OutlineMethod),
    /// Blurred outline: the selected objects (mark), then their copies (outline), into the mask.
    Mask,
    /// Blurred outline: one 1D box pass of `radius` texels, along x or y.
    Blur { along_x: bool, radius: u32 },
}

impl DrawKind for OutlineDraw {
    fn describe(self) -> &'static str {
        match self {
            OutlineDraw::NotSelected => "objects not selected",
            OutlineDraw::Selected => "selected objects",
            OutlineDraw::Copies(OutlineMethod::Extrude) => "selected objects' extruded copies",
            OutlineDraw::Copies(OutlineMethod::Scale) => "selected objects' scaled-up copies",
            OutlineDraw::Mask => "selected objects (mark), then their copies (outline)",
            OutlineDraw::Blur { .. } => "full screen",
        }
    }
}

/// The outline's descriptor sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OutlineSet {
    Ramps,
    /// The mask, sampled by the first blur pass.
    Mask,
    /// The first blur's result, sampled by the second.
    BlurredAlongX,
    /// The blurred mask and the mask (for its selection mark), sampled by the apply pass.
    Blurred,
}

impl Label for OutlineSet {
    fn label(self) -> &'static str {
        match self {
            OutlineSet::Ramps => "toon ramps",
            OutlineSet::Mask => "outline mask",
            OutlineSet::BlurredAlongX => "outline blurred along x",
            OutlineSet::Blurred => "blurred outline and mask",
        }
    }
}

impl WithRamps for OutlineSet {
    const RAMPS: Self = OutlineSet::Ramps;
}

/// The blurred outline's render passes, before the frame's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OutlineTarget {
    /// The sharp outline as a mask: R = outline, A = selected.
    Mask,
    /// The mask blurred along x.
    BlurX,
    /// Then along y.
    BlurY,
}

impl Label for OutlineTarget {
    fn label(self) -> &'static str {
        match self {
            OutlineTarget::Mask => "outline mask",
            OutlineTarget::BlurX => "outline blur x",
            OutlineTarget::BlurY => "outline blur y",
        }
    }
}
