//! The planar family's options, as plain data and as their own flags (`clap::Args`, flattened
//! into the command line).

use crate::error::{Error, Result};
use crate::technique::flags::clap_defaults;

/// The planar family's options (`planar`, `blob`, `shadow-texture`), and their flags. How dark
/// the shadow is is `RenderOptions::shadow_tone` (its darkest factor: these shadows darken every
/// channel alike).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, clap::Args)]
pub struct PlanarOptions {
    /// Draw the projected shadows (off: the scene pass alone, GPU-skinned, with the receiver
    /// mask in alpha: what the tests compare against).
    #[arg(skip = true)]
    pub shadows: bool,
    // `None`: the lowest flat horizontal non-caster is found.
    #[command(flatten)]
    pub plane: Option<GivenPlane>,
    // In (0, 1]; `None`: from the full mesh.
    /// planar, shadow-texture: cast the shadow from each caster simplified with meshoptimizer
    /// to about this fraction of its triangles (0 < RATIO <= 1; `bench` adds a variant with it).
    #[arg(long, value_name = "RATIO")]
    pub shadow_lod: Option<f32>,
    /// shadow-texture: side of the texture the casters are drawn into from the light, in texels
    /// (the seed's render texture; small on purpose).
    #[arg(id = "render_texture_size", long = "render-texture-size", default_value_t = DEFAULT_TEXTURE_SHADOW_SIZE, value_name = "N")]
    pub texture_size: u32,
    /// shadow-texture: show the texture on the `receivers` drawn again (clipped to them) or, as
    /// the seed does, on one `quad` on the plane around the casters' shadow.
    #[arg(
        id = "render_texture_on",
        long = "render-texture-on",
        value_name = "RENDER_TEXTURE_ON",
        value_enum,
        default_value_t
    )]
    pub texture_on: TextureShadowOn,
}

crate::names::named_enum! {
    /// Where `shadow-texture` shows its texture.
    pub enum TextureShadowOn {
        /// The receivers drawn again, each pixel looking the texture up: clipped to them.
        #[default]
        Receivers = "receivers",
        /// The seed's way: one quad on the plane around the casters' shadow, textured with it.
        Quad = "quad",
    }
}

/// Default side of `shadow-texture`'s texture (small on purpose: what a phone can spare).
pub const DEFAULT_TEXTURE_SHADOW_SIZE: u32 = 128;

impl Default for PlanarOptions {
    fn default() -> Self {
        clap_defaults()
    }
}

impl PlanarOptions {
    /// Checks the numbers a user typed.
    pub fn check(&self) -> Result<()> {
        if let Some(ratio) = self.shadow_lod {
            if !(ratio.is_finite() && ratio > 0.0 && ratio <= 1.0) {
                return Err(Error::InvalidInput(format!(
                    "--shadow-lod {ratio}: the fraction of triangles kept must be above 0 and at most 1"
                )));
            }
        }
        if !(4..=crate::gpu::mobile_profile::MAX_IMAGE_SIDE).contains(&self.texture_size) {
            return Err(Error::InvalidInput(format!(
                "--render-texture-size {}: use 4 to {} texels",
                self.texture_size,
                crate::gpu::mobile_profile::MAX_IMAGE_SIDE
            )));
        }
        match self.plane {
            Some(plane) => plane.check(),
            None => Ok(()),
        }
    }
}

// A receiving plane given by the user (`--plane-normal X,Y,Z`, `--plane-height H`): the plane
// with normal `normal` (any length but zero) through the point (0, H, 0). Flattened as an
// `Option` into `PlanarOptions`: `None` unless one of its flags is given.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, clap::Args)]
pub struct GivenPlane {
    /// planar, shadow-texture, blob: the receiving plane crosses the y axis at H (default: the
    /// lowest flat horizontal non-caster is the ground).
    #[arg(
        id = "plane_height",
        long = "plane-height",
        value_name = "H",
        allow_hyphen_values = true,
        default_value_t = 0.0,
        hide_default_value = true
    )]
    pub height: f32,
    /// planar, shadow-texture: the receiving plane's normal (any length but zero; default
    /// 0,1,0), projected onto with Blinn's shadow matrix; e.g. `--scene slope --plane-normal 0,3,1`.
    #[arg(
        id = "plane_normal", long = "plane-normal",
        value_name = "X,Y,Z",
        allow_hyphen_values = true,
        default_value = "0,1,0",
        hide_default_value = true,
        value_parser = parse_plane_normal
    )]
    pub normal: [f32; 3],
}

impl Default for GivenPlane {
    fn default() -> Self {
        clap_defaults()
    }
}

/// `--plane-normal`'s value, for clap (which names the option and the value).
fn parse_plane_normal(text: &str) -> std::result::Result<[f32; 3], String> {
    GivenPlane::parse_normal(text).map_err(|_| "expected three numbers X,Y,Z".to_owned())
}

impl GivenPlane {
    /// A finite height and a finite, non-zero normal.
    pub fn check(&self) -> Result<()> {
        if !self.height.is_finite() {
            return Err(Error::InvalidInput(format!("--plane-height {}: not a finite number", self.height)));
        }
        let [x, y, z] = self.normal;
        if !self.normal.iter().all(|c| c.is_finite()) || (x * x + y * y + z * z).sqrt() < 1e-6 {
            return Err(Error::InvalidInput(format!(
                "--plane-normal {x},{y},{z}: a plane needs a finite, non-zero normal"
            )));
        }
        Ok(())
    }

    /// Parses `X,Y,Z` as given to `--plane-normal`.
    pub fn parse_normal(text: &str) -> Result<[f32; 3]> {
        let bad = || Error::InvalidInput(format!("--plane-normal '{text}': expected three numbers X,Y,Z"));
        let parts: Vec<f32> = text
            .split(',')
            .map(|p| p.trim().parse::<f32>())
            .collect::<std::result::Result<_, _>>()
            .map_err(|_| bad())?;
        <[f32; 3]>::try_from(parts).map_err(|_| bad())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_the_flags_defaults() {
        let planar = PlanarOptions::default();
        assert_eq!(planar.plane, None, "no plane flag given: the plane is found");
        assert!(planar.shadows && planar.shadow_lod.is_none());
        assert_eq!((planar.texture_size, planar.texture_on), (DEFAULT_TEXTURE_SHADOW_SIZE, TextureShadowOn::Receivers));
        assert_eq!(GivenPlane::default(), GivenPlane { normal: [0.0, 1.0, 0.0], height: 0.0 });
    }
}
