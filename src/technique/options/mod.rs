//! The options of every family, one file each, named after it (`shadow_volume`, `planar`,
//! `cartoon`, `shadow_atlas`), and the shadow mode every shadowing family reads. They are the
//! command line's and the library's vocabulary, which `RenderOptions` holds: below every family,
//! so that a family reads its own and the generic interface names them all without importing
//! from a family. What their flags share is in `flags`. (Which technique, the size and the
//! stencil path are in `RenderOptions`, beside the `Technique` interface.)

mod cartoon;
mod planar;
mod shadow_atlas;
mod shadow_volume;

use super::light_loop::ShadowedLights;

pub use cartoon::{CartoonOptions, InkStyle, InkStyles, OutlineMethod, Seams, SilhouetteMethod};
pub use planar::{GivenPlane, PlanarOptions, TextureShadowOn};
pub use shadow_atlas::{AtlasBake, LightMode, ShadowAtlasOptions, ShadowKind};
pub use shadow_volume::{Normalize, ShadowVolumeOptions, VolumeExtrusion, VolumeMethod};

crate::names::named_enum! {
    /// What a shadow does to the frame.
    pub enum ShadowMode {
        /// Doom 3's and Ogre's additive loop: ambient first, then each light added where its
        /// own shadow does not fall. A shadow removes only its light.
        #[default]
        Additive = "additive",
        /// The seed's apply (Hall): the finished, lit frame darkened where the primary light's
        /// shadow falls.
        Modulate = "modulate",
    }
}

impl ShadowMode {
    /// The lights a family with both modes shadows: every one in the additive loop, the primary
    /// light in the seeds' modulated frame.
    pub fn shadowed_lights(self) -> ShadowedLights {
        match self {
            ShadowMode::Additive => ShadowedLights::Every,
            ShadowMode::Modulate => ShadowedLights::Primary,
        }
    }
}
