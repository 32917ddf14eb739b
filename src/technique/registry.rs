//! The list of techniques: the only place that names them all. The command line, `passes`,
//! `bench`, `profile --compare`, `info` and the viewer read it.

use super::interface::{RenderOptions, Technique};
use super::light_loop::ShadowedLights;
use super::options::ShadowMode;
use crate::error::{Error, Result};
use crate::frame::StencilMode;

/// What `render`, `profile`, `bench`, `passes` and `view` use when no `--technique` is given:
/// the project's point, stencil-free shadow volumes.
pub const DEFAULT_TECHNIQUE: &str = "shadow-volume";

/// Every technique, in the order `info`, `--help` and the viewer's T key list them.
pub static TECHNIQUES: &[Technique] = &[
    Technique(&super::lit::Lit),
    Technique(&super::shadow_volume::ShadowVolumes),
    Technique(&super::outline::Outline),
    Technique(&super::ink::SILHOUETTE),
    Technique(&super::ink::TOON),
    Technique(&super::planar::Planar),
    Technique(&super::planar::BlobShadows),
    Technique(&super::planar::ShadowTexture),
    Technique(&super::shadow_atlas::SHADOW_MAP),
    Technique(&super::shadow_atlas::SHADOW_TEXTURE_ATLAS),
    Technique(&super::shadow_atlas::PROJECTIVE_TEXTURE),
    Technique(&super::xray::XRay),
];

impl Default for RenderOptions {
    /// The lit scene at 256x256, stencil emulated, every family's default options.
    fn default() -> Self {
        RenderOptions {
            width: 256,
            height: 256,
            stencil: StencilMode::Emulated,
            technique: Technique(&super::lit::Lit),
            shadow_volume: Default::default(),
            shadow_mode: Default::default(),
            shadow_tone: Default::default(),
            shadow_atlas: Default::default(),
            count_overdraw: false,
            cartoon: Default::default(),
            planar: Default::default(),
            samples: 1,
            keep_samples: false,
            destination: Default::default(),
            frames_in_flight: 1,
            skinning: Default::default(),
        }
    }
}

/// The technique called `name`.
pub fn by_name(name: &str) -> Result<Technique> {
    TECHNIQUES
        .iter()
        .copied()
        .find(|t| t.name() == name)
        .ok_or_else(|| Error::InvalidInput(format!("unknown technique '{name}'; available: {}", names().join(", "))))
}

/// The techniques that shadow every light in the additive mode (`--shadow-mode additive`,
/// the default), asked of each technique, in list order: what a user whose technique leaves
/// lights unshadowed can switch to (`nostencil info` lists them).
pub fn shadowing_every_light() -> Vec<&'static str> {
    let additive = RenderOptions { shadow_mode: ShadowMode::Additive, ..RenderOptions::default() };
    TECHNIQUES.iter().filter(|t| t.shadowed_lights(&additive, &[]) == ShadowedLights::Every).map(|t| t.name()).collect()
}

/// Every technique's name, in list order.
pub fn names() -> Vec<&'static str> {
    TECHNIQUES.iter().map(|t| t.name()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_found() {
        let mut seen = std::collections::HashSet::new();
        for technique in TECHNIQUES {
            assert!(seen.insert(technique.name()), "{} listed twice", technique.name());
            assert_eq!(by_name(technique.name()).map(|t| t.name()).ok(), Some(technique.name()));
        }
        assert!(by_name("nope").is_err());
    }

    #[test]
    fn the_families_of_the_additive_loop_shadow_every_light() {
        assert_eq!(shadowing_every_light(), ["shadow-volume", "planar"]);
    }
}
