//! The options of each technique family, as plain data: what the command line, the viewer and
//! a port set. (Which technique, the size and the stencil path are in `RenderOptions`, beside
//! the `Technique` interface.)

use crate::error::{Error, Result};

/// How volume walls are counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum VolumeMethod {
    /// z-fail when the camera (or its near plane) is inside a volume, else z-pass.
    #[default]
    Auto,
    ZPass,
    ZFail,
}

/// How the count becomes a shadow mask.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Normalize {
    /// The seed's fixed-function sequence: N0, iterations, REVERSE_SUBTRACT D, ADD D, apply.
    #[default]
    Seed,
    /// As `seed`, with one MAX pass in place of the two D passes.
    Max,
    /// One full-screen pass reading the count as an input attachment.
    Subpass,
}

impl VolumeMethod {
    pub fn parse(text: &str) -> Result<Self> {
        match text {
            "auto" => Ok(VolumeMethod::Auto),
            "zpass" => Ok(VolumeMethod::ZPass),
            "zfail" => Ok(VolumeMethod::ZFail),
            _ => Err(Error::InvalidInput(format!("--volume-method {text}: use auto, zpass or zfail"))),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            VolumeMethod::Auto => "auto",
            VolumeMethod::ZPass => "z-pass",
            VolumeMethod::ZFail => "z-fail",
        }
    }
}

impl Normalize {
    pub const ALL: [Normalize; 3] = [Normalize::Seed, Normalize::Max, Normalize::Subpass];

    pub fn parse(text: &str) -> Result<Self> {
        match text {
            "seed" => Ok(Normalize::Seed),
            "max" => Ok(Normalize::Max),
            "subpass" => Ok(Normalize::Subpass),
            _ => Err(Error::InvalidInput(format!("--normalize {text}: use seed, max or subpass"))),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Normalize::Seed => "seed",
            Normalize::Max => "max",
            Normalize::Subpass => "subpass",
        }
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

/// Which of the two seed 004 shadow techniques a renderer draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowKind {
    /// Shadow textures baked into each model's atlas (the paper's method).
    Atlas,
    /// The shadow map sampled in the scene pass.
    Map,
}

impl ShadowKind {
    pub fn name(self) -> &'static str {
        match self {
            ShadowKind::Atlas => "shadow-texture-atlas",
            ShadowKind::Map => "shadow-map",
        }
    }
}

/// `--light`: whether the light turns from frame to frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LightMode {
    /// Turns about the vertical by a small step a frame: every frame re-bakes.
    Moving,
    /// Stays put: after the first frame the shadow map and bake are skipped.
    #[default]
    Fixed,
}

impl LightMode {
    pub fn parse(text: &str) -> Result<Self> {
        match text {
            "moving" => Ok(LightMode::Moving),
            "fixed" => Ok(LightMode::Fixed),
            _ => Err(Error::InvalidInput(format!("--light {text}: use moving or fixed"))),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            LightMode::Moving => "moving",
            LightMode::Fixed => "fixed",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ShadowAtlasOptions {
    /// Shadow map side in texels (the paper: 512).
    pub map_size: u32,
    /// Shadow texture side for meshes that are not geometry images (those use n - 1 rounded
    /// up to a power of two: 256 for 257x257, 64 for 64x64).
    pub texture_size: u32,
    pub light: LightMode,
}

impl Default for ShadowAtlasOptions {
    fn default() -> Self {
        ShadowAtlasOptions { map_size: 512, texture_size: 256, light: LightMode::Fixed }
    }
}

/// Checks a shadow map or shadow texture side: a power of two in 16..=4096.
pub fn check_size(what: &str, size: u32) -> Result<u32> {
    if !(16..=4096).contains(&size) || !size.is_power_of_two() {
        return Err(Error::InvalidInput(format!("{what} {size}: use a power of two from 16 to 4096")));
    }
    Ok(size)
}
