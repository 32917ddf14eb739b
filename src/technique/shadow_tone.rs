//! How dark a shadow is: the shadowed colour's factor, one grey byte or a tint per channel. Shared
//! by the shadow volumes and the planar family (`RenderOptions::shadow_tone`), parsed once from
//! `--shadow-factor F` or `--shadow-colour #RRGGBB` ([`SharedShadowArgs`]), and turned into the
//! floats the blend constants and push constants carry in one place ([`ShadowTone::factors`]).

use glam::Vec3;

use super::flags::parse_rgb_hex;
use super::options::ShadowMode;

/// A shadowed pixel's colour is its colour times these factors, in 1/255 steps (8-bit values, so
/// that every path multiplies by exactly the same number).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowTone {
    /// Colour x F/255 on every channel (`--shadow-factor F`).
    Grey(u8),
    /// Colour x R/255, G/255, B/255, channel by channel (`--shadow-colour #RRGGBB`; linear
    /// factors, as the blend unit multiplies). Seed 000's apply modulates with a shadow colour.
    Tinted([u8; 3]),
}

impl ShadowTone {
    /// `--shadow-factor`'s default: 102/255, a shadowed pixel keeps 40% of its colour.
    pub const DEFAULT_FACTOR: u8 = 102;

    /// The factor per channel (R, G, B), in 1/255.
    pub fn rgb(self) -> [u8; 3] {
        match self {
            ShadowTone::Grey(f) => [f; 3],
            ShadowTone::Tinted(rgb) => rgb,
        }
    }

    /// The darkest channel's factor: what the blend-only normalisation must bring every count
    /// to, and the one factor of the planar family (which darkens all channels alike).
    pub fn darkest(self) -> u8 {
        let [r, g, b] = self.rgb();
        r.min(g).min(b)
    }

    /// The factors as the GPU multiplies by them: byte / 255 (see [`Self::factor`]).
    pub fn factors(self) -> [f32; 3] {
        self.rgb().map(ShadowTone::factor)
    }

    /// One factor byte as the GPU multiplies by it: byte / 255. The only conversion.
    pub fn factor(byte: u8) -> f32 {
        f32::from(byte) / 255.0
    }

    /// [`Self::factors`] as a vector.
    pub fn vec3(self) -> Vec3 {
        Vec3::from_array(self.factors())
    }

    /// The darkest factor as the GPU multiplies by it (the planar family's one factor).
    pub fn darkest_factor(self) -> f32 {
        ShadowTone::factor(self.darkest())
    }
}

impl Default for ShadowTone {
    fn default() -> Self {
        ShadowTone::Grey(ShadowTone::DEFAULT_FACTOR)
    }
}

/// The flags the shadow-volume and planar families share, flattened into every command that
/// renders shadows (and `passes`): the frame's loop, [`ShadowMode`], and the two that give a
/// [`ShadowTone`]. Both go into `RenderOptions`, where every family reads them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::Args)]
pub struct SharedShadowArgs {
    /// shadow-volume and planar: `additive` (ambient, then each light added where its own shadow
    /// does not fall: Doom 3's and Ogre's loop) or `modulate` (the seeds' frame: the lit frame
    /// darkened where the primary light's shadow falls).
    #[arg(long = "shadow-mode", value_name = "MODE", value_enum, default_value_t)]
    pub shadow_mode: ShadowMode,
    /// shadow-volume, planar, blob, shadow-texture: shadowed colour = colour x F/255 (0..=255;
    /// 255: no shadow). For shadow volumes the normalisation's iteration count follows it.
    #[arg(long, default_value_t = ShadowTone::DEFAULT_FACTOR, value_name = "F")]
    pub shadow_factor: u8,
    /// shadow-volume: a tinted shadow (seed 000's apply modulates with a shadow colour):
    /// shadowed colour = colour x RR/255, GG/255, BB/255 per channel, linear factors given in hex
    /// (`#RRGGBB` or `RRGGBB`), in every path. Instead of --shadow-factor. (The planar family
    /// darkens all channels alike, by the darkest.)
    #[arg(long, value_name = "#RRGGBB", value_parser = parse_rgb8, conflicts_with = "shadow_factor")]
    pub shadow_colour: Option<[u8; 3]>,
}

impl SharedShadowArgs {
    /// The tone the flags give: the tint if there is one, else the grey factor.
    pub fn tone(&self) -> ShadowTone {
        match self.shadow_colour {
            Some(rgb) => ShadowTone::Tinted(rgb),
            None => ShadowTone::Grey(self.shadow_factor),
        }
    }
}

/// `#RRGGBB` or `RRGGBB` as three bytes, for clap (the one parser is `parse_rgb_hex`).
pub(crate) fn parse_rgb8(text: &str) -> std::result::Result<[u8; 3], String> {
    parse_rgb_hex("colour", text).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_conversion_gives_the_bytes_over_255() {
        let grey = ShadowTone::Grey(102);
        assert_eq!(grey.rgb(), [102; 3]);
        assert_eq!(grey.darkest(), 102);
        assert_eq!(grey.factors(), [102.0 / 255.0; 3]);
        let tint = ShadowTone::Tinted([51, 128, 204]);
        assert_eq!(tint.darkest(), 51);
        assert_eq!(tint.vec3(), Vec3::new(51.0 / 255.0, 128.0 / 255.0, 204.0 / 255.0));
        assert_eq!(tint.darkest_factor(), 51.0 / 255.0);
        assert_eq!(ShadowTone::default(), ShadowTone::Grey(ShadowTone::DEFAULT_FACTOR));
    }
}
