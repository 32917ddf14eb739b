//! The shadow-atlas family's options (shadow map, shadow-texture atlas, projective texture), as
//! plain data and as their own flags (`clap::Args`, flattened into the command line).

use crate::error::{Error, Result};
use crate::technique::flags::clap_defaults;

/// Which of the two seed 004 shadow techniques a renderer draws. Not a command-line value
/// (the technique is): JSON keeps its short spelling, `name()` is the technique's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowKind {
    /// Shadow textures baked into each model's tile of an atlas page (the paper's method).
    Atlas,
    /// The shadow map sampled in the scene pass.
    Map,
    /// Each model's shadow texture projected from the light (Segal et al.'s shadow texture,
    /// the paper's figure 2): one texel stands for every surface point on its light ray, so a
    /// concave model's lit parts take the shadow of its parts behind them.
    Projective,
}

impl ShadowKind {
    /// The technique that draws it.
    pub fn name(self) -> &'static str {
        match self {
            ShadowKind::Atlas => "shadow-texture-atlas",
            ShadowKind::Map => "shadow-map",
            ShadowKind::Projective => "projective-texture",
        }
    }
}

crate::names::named_enum! {
    /// `--light-motion`: whether the light turns from frame to frame.
    pub enum LightMode {
        /// Turns about the vertical by a small step a frame: every frame re-bakes.
        Moving = "moving",
        /// Stays put: after the first frame the shadow map and bake are skipped.
        #[default]
        Fixed = "fixed",
    }
}

crate::names::named_enum! {
    /// `--atlas-bake`: how a shadow texture whose atlas covers every texel is baked.
    pub enum AtlasBake {
        /// One fragment per texel, from the surface point the texel holds (seed 004's geometry
        /// images, and a mesh mapped whole onto its square); meshes whose charts leave a
        /// gutter, and skins, are rasterised all the same.
        #[default]
        Texels = "texels",
        /// Every mesh's triangles drawn at their atlas UVs (the general bake), for comparison.
        Rasterised = "rasterised",
    }
}

/// The shadow-map family's options (`shadow-map`, `shadow-texture-atlas`,
/// `projective-texture`), and their flags.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, clap::Args)]
pub struct ShadowAtlasOptions {
    /// shadow-map, shadow-texture-atlas, projective-texture: `moving` (turns every frame:
    /// re-bake) or `fixed` (after the first frame the shadow map and bake are skipped).
    #[arg(id = "light_motion", long = "light-motion", value_enum, default_value_t, value_name = "moving|fixed")]
    pub light: LightMode,
    // The paper: 512.
    /// shadow-map, shadow-texture-atlas, projective-texture: shadow map side in texels (power of
    /// two; also the projective texture's side).
    #[arg(id = "shadow_map_size", long = "shadow-map-size", default_value_t = 512, value_name = "N")]
    pub map_size: u32,
    // Geometry images use n - 1 rounded up to a power of two: 256 for 257x257, 64 for 64x64.
    /// shadow-texture-atlas: shadow texture side for meshes that are not geometry images.
    #[arg(id = "shadow_texture_size", long = "shadow-texture-size", default_value_t = 256, value_name = "N")]
    pub texture_size: u32,
    /// shadow-texture-atlas: bake geometry images (and meshes whose atlas covers every texel)
    /// by their `texels` (one fragment a texel) or `rasterised` like every other mesh (their
    /// triangles at their atlas UVs), to compare.
    #[arg(id = "atlas_bake", long = "atlas-bake", value_enum, default_value_t, value_name = "texels|rasterised")]
    pub bake: AtlasBake,
}

impl Default for ShadowAtlasOptions {
    fn default() -> Self {
        clap_defaults()
    }
}

/// Checks a shadow map or shadow texture side: a power of two in 16..=4096.
pub fn check_size(what: &str, size: u32) -> Result<u32> {
    if !(16..=4096).contains(&size) || !size.is_power_of_two() {
        return Err(Error::InvalidInput(format!("{what} {size}: use a power of two from 16 to 4096")));
    }
    Ok(size)
}

impl ShadowAtlasOptions {
    /// Checks the map and texture sides (powers of two in 16..=4096).
    pub fn check(&self) -> Result<()> {
        check_size("--shadow-map-size", self.map_size)?;
        check_size("--shadow-texture-size", self.texture_size).map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_the_flags_defaults() {
        let atlas = ShadowAtlasOptions::default();
        assert_eq!((atlas.map_size, atlas.texture_size, atlas.light), (512, 256, LightMode::Fixed));
    }
}
