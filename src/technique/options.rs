//! Everything that selects how a frame is rendered: size, stencil path, technique, and each
//! technique family's own options.

use super::interface::Technique;
use super::{CartoonOptions, PlanarOptions, ShadowAtlasOptions, ShadowVolumeOptions};
use crate::frame::StencilMode;

#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    pub stencil: StencilMode,
    pub technique: &'static dyn Technique,
    pub shadow_volume: ShadowVolumeOptions,
    pub shadow_atlas: ShadowAtlasOptions,
    /// Heat-map frame: alpha ends up holding the fragments shaded per pixel.
    pub count_overdraw: bool,
    pub cartoon: CartoonOptions,
    pub planar: PlanarOptions,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 256,
            height: 256,
            stencil: StencilMode::Emulated,
            technique: &super::lit::Lit,
            shadow_volume: ShadowVolumeOptions::default(),
            shadow_atlas: ShadowAtlasOptions::default(),
            count_overdraw: false,
            cartoon: CartoonOptions::default(),
            planar: PlanarOptions::default(),
        }
    }
}

impl RenderOptions {
    /// These options with another technique.
    pub fn with_technique(&self, technique: &'static dyn Technique) -> Self {
        RenderOptions { technique, ..self.clone() }
    }
}
