//! Every family's options in one place: the shadow mode every shadowing family reads, and each
//! family's own options, which live beside it (`shadow_volume/options.rs`, `planar/options.rs`,
//! `cartoon_options.rs`, `shadow_atlas/options.rs`) and are re-exported here. What their flags
//! share is in `flags`. (Which technique, the size and the stencil path are in
//! `RenderOptions`, beside the `Technique` interface.)

use super::light_loop::ShadowedLights;

pub use super::cartoon_options::{CartoonOptions, InkStyle, InkStyles, OutlineMethod, Seams, SilhouetteMethod};
pub use super::planar::options::{GivenPlane, PlanarOptions, TextureShadowOn};
pub use super::shadow_atlas::light::MOVING_LIGHT_STEP;
pub use super::shadow_atlas::options::{AtlasBake, LightMode, ShadowAtlasOptions, ShadowKind};
pub use super::shadow_volume::options::{Normalize, ShadowVolumeOptions, VolumeMethod};

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
