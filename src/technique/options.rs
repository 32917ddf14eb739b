//! The options of each technique family, as plain data: what the command line, the viewer and
//! a port set. (Which technique, the size and the stencil path are in `RenderOptions`, beside
//! the `Technique` interface.)

use crate::error::{Error, Result};

crate::names::named_enum! {
    /// How volume walls are counted.
    pub enum VolumeMethod {
        /// z-fail when the camera (or its near plane) is inside a volume, else z-pass.
        #[default]
        Auto = "auto",
        ZPass = "zpass",
        ZFail = "zfail",
    }
}

crate::names::named_enum! {
    /// How the count becomes a shadow mask.
    pub enum Normalize {
        /// The seed's fixed-function sequence: N0, iterations, REVERSE_SUBTRACT D, ADD D, apply.
        #[default]
        Seed = "seed",
        /// As `seed`, with one MAX pass in place of the two D passes.
        Max = "max",
        /// One full-screen pass reading the count as an input attachment.
        Subpass = "subpass",
    }
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ShadowVolumeOptions {
    /// k: each volume wall adds or removes k/255 of alpha (1..=8).
    pub increment: u8,
    pub method: VolumeMethod,
    pub normalize: Normalize,
    /// Shadowed colour = colour x shadow_factor/255. An 8-bit value, so that every path
    /// multiplies by exactly the same number.
    pub shadow_factor: u8,
}

impl Default for ShadowVolumeOptions {
    fn default() -> Self {
        ShadowVolumeOptions { increment: 1, method: VolumeMethod::Auto, normalize: Normalize::Seed, shadow_factor: 102 }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PlanarOptions {
    /// Shadowed receiver colour = colour x shadow_factor/255 (`1 - s` as an 8-bit value, so that
    /// both paths multiply by exactly the same number).
    pub shadow_factor: u8,
    /// Draw the projected shadows (off: the scene pass alone, GPU-skinned, with the receiver
    /// mask in alpha: what the tests compare against).
    pub shadows: bool,
}

impl Default for PlanarOptions {
    fn default() -> Self {
        PlanarOptions { shadow_factor: 102, shadows: true }
    }
}

crate::names::named_enum! {
    /// How `silhouette` and `toon` find their ink.
    pub enum SilhouetteMethod {
        /// CPU edge classification, screen-space quads.
        #[default]
        Edges = "edges",
        /// N.V per vertex looked up in a 1D texture (dark rim).
        Shader = "shader",
        /// Normal-extruded inverted hull.
        Hull = "hull",
    }
}

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CartoonOptions {
    /// Objects to outline (`outline`); empty: the scene's first closed object.
    pub select: Vec<String>,
    pub silhouette: SilhouetteMethod,
    /// Edges whose faces fold by more than this many degrees are creases.
    pub crease_deg: f32,
    /// Ink line width in pixels (edges), and the width of the hull rim.
    pub line_width: f32,
    /// Outline width in pixels (`outline`).
    pub outline_width: f32,
    /// Outline colour, 8-bit RGB (so every path writes the same bytes).
    pub outline_colour: [u8; 3],
}

impl Default for CartoonOptions {
    fn default() -> Self {
        CartoonOptions {
            select: Vec::new(),
            silhouette: SilhouetteMethod::Edges,
            crease_deg: 40.0,
            line_width: 2.0,
            outline_width: 4.0,
            outline_colour: [255, 160, 0],
        }
    }
}

impl CartoonOptions {
    /// Checks the numbers a user typed.
    pub fn check(&self) -> Result<()> {
        if !(self.line_width.is_finite() && (0.5..=64.0).contains(&self.line_width)) {
            return Err(Error::InvalidInput(format!("--line-width {}: use 0.5 to 64 pixels", self.line_width)));
        }
        if !(self.outline_width.is_finite() && (0.5..=64.0).contains(&self.outline_width)) {
            return Err(Error::InvalidInput(format!("--outline-width {}: use 0.5 to 64 pixels", self.outline_width)));
        }
        if !(self.crease_deg.is_finite() && (0.0..=180.0).contains(&self.crease_deg)) {
            return Err(Error::InvalidInput(format!("--crease-angle {}: use 0 to 180 degrees", self.crease_deg)));
        }
        Ok(())
    }

    /// Parses `--select NAME,NAME,...` (empty: the default selection).
    pub fn parse_select(text: &str) -> Vec<String> {
        text.split(',').map(str::trim).filter(|s| !s.is_empty()).map(str::to_owned).collect()
    }
}
