//! The options of each technique family, as plain data: what the command line, the viewer and
//! a port set. (Which technique, the size and the stencil path are in `RenderOptions`, beside
//! the `Technique` interface.)

use super::alpha_counter;
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
    /// A tinted shadow (seed 000's apply modulates with a shadow colour): shadowed colour =
    /// colour x these factors / 255, per channel (linear, as the blend unit multiplies).
    /// Overrides `shadow_factor`.
    pub shadow_colour: Option<[u8; 3]>,
    /// Add the full-screen saturation probe (docs/design/saturation.md): a diagnostic pass a user
    /// asks for, never part of a timed frame. The `subpass` apply counts saturation without it.
    pub saturation_probe: bool,
    /// The device has `fragmentStoresAndAtomics` (Android Baseline 2022), so the `subpass`
    /// apply counts saturated samples with one atomic add per pixel. The renderer turns it off on a
    /// device without the feature; a plan printed without a device assumes the baseline.
    pub fragment_atomics: bool,
    /// Volumes end just past the receivers' bounds and each is scissored to where it can shade,
    /// the apply to their union, in both paths alike (docs/shadow-volumes.md, "Volumes clipped to
    /// where they can shade"). Off: every volume reaches infinity over the whole frame, to measure what
    /// clipping saves.
    pub clip_volumes: bool,
}

impl Default for ShadowVolumeOptions {
    fn default() -> Self {
        ShadowVolumeOptions {
            increment: 1,
            method: VolumeMethod::Auto,
            normalize: Normalize::Seed,
            shadow_factor: 102,
            shadow_colour: None,
            saturation_probe: false,
            fragment_atomics: true,
            clip_volumes: true,
        }
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
    /// The receiving plane as the user gives it; `None`: the lowest flat horizontal
    /// non-caster is found.
    pub plane: Option<GivenPlane>,
    /// Cast the shadow from each caster simplified (meshoptimizer) to about this fraction of
    /// its triangles, in (0, 1]; `None`: from the full mesh.
    pub shadow_lod: Option<f32>,
    /// `shadow-texture`: the side of the texture the casters are drawn into from the light.
    pub texture_size: u32,
    /// `shadow-texture`: what shows the texture: the receivers drawn again, or a quad.
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
        PlanarOptions {
            shadow_factor: 102,
            shadows: true,
            plane: None,
            shadow_lod: None,
            texture_size: DEFAULT_TEXTURE_SHADOW_SIZE,
            texture_on: TextureShadowOn::Receivers,
        }
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

/// A receiving plane given by the user (`--plane-normal X,Y,Z`, `--plane-height H`): the plane
/// with normal `normal` (any length but zero) through the point (0, H, 0).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct GivenPlane {
    pub normal: [f32; 3],
    pub height: f32,
}

impl Default for GivenPlane {
    fn default() -> Self {
        GivenPlane { normal: [0.0, 1.0, 0.0], height: 0.0 }
    }
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
        /// Dietrich's alpha test: N.V per pixel as alpha, ink where it is at most `--alpha-ref`.
        AlphaTest = "alpha-test",
        /// The seed's two-pass extrusion, per object: its copy pushed out along the normals,
        /// depth test and write off, in ink; then the object, depth on.
        Extrusion = "extrusion",
    }
}

/// One edge class's ink (`--ink-silhouette`, `--ink-crease`, `--ink-boundary`): what is unset
/// follows `--line-width` and the default ink colour.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct InkStyle {
    /// Line width in pixels.
    pub width: Option<f32>,
    /// 8-bit sRGB colour, as the frame stores it.
    pub colour: Option<[u8; 3]>,
}

/// `--seams`: which attribute jumps across an edge make it a boundary (edges method), as the
/// seed defines boundaries: vertices that differ in normal, texture coordinate or material.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Seams {
    pub normal: bool,
    pub uv: bool,
    /// Borders between the primitives (one material each) of one glTF mesh.
    pub material: bool,
}

impl Default for Seams {
    fn default() -> Self {
        Seams { normal: true, uv: false, material: true }
    }
}

impl Seams {
    /// Parses `--seams normal,uv,material` (any of them, or `none`).
    pub fn parse(text: &str) -> Result<Seams> {
        let mut seams = Seams { normal: false, uv: false, material: false };
        for word in text.split(',').map(str::trim) {
            match word {
                "normal" => seams.normal = true,
                "uv" => seams.uv = true,
                "material" => seams.material = true,
                "none" | "" => {}
                other => {
                    return Err(Error::InvalidInput(format!(
                        "--seams '{other}': use normal, uv, material or none, comma-separated"
                    )))
                }
            }
        }
        Ok(seams)
    }
}

/// The command-line flag of each edge class's style, in the order of `CartoonOptions::ink`.
pub const INK_STYLE_FLAGS: [&str; 3] = ["--ink-silhouette", "--ink-crease", "--ink-boundary"];

impl InkStyle {
    /// Parses `WIDTH`, `WIDTH,#RRGGBB` or `#RRGGBB` (the `#` is optional), for `flag`.
    pub fn parse(flag: &str, text: &str) -> Result<InkStyle> {
        let bad = |why: &str| Error::InvalidInput(format!("{flag} '{text}': {why}; expected WIDTH[,#RRGGBB]"));
        let (width, colour) = match text.split_once(',') {
            Some((width, colour)) => (Some(width.trim()), Some(colour.trim())),
            None if text.trim().starts_with('#') => (None, Some(text.trim())),
            None => (Some(text.trim()), None),
        };
        let width = match width {
            Some(w) => Some(w.parse::<f32>().map_err(|_| bad("the width is not a number"))?),
            None => None,
        };
        let colour = match colour {
            Some(c) => {
                let hex = c.strip_prefix('#').unwrap_or(c);
                let channel = |i: usize| hex.get(i..i + 2).and_then(|h| u8::from_str_radix(h, 16).ok());
                match (hex.len(), channel(0), channel(2), channel(4)) {
                    (6, Some(r), Some(g), Some(b)) => Some([r, g, b]),
                    _ => return Err(bad("the colour is not six hex digits")),
                }
            }
            None => None,
        };
        let style = InkStyle { width, colour };
        style.check(flag)?;
        Ok(style)
    }

    fn check(&self, flag: &str) -> Result<()> {
        match self.width {
            Some(w) if !(w.is_finite() && (0.5..=64.0).contains(&w)) => {
                Err(Error::InvalidInput(format!("{flag} width {w}: use 0.5 to 64 pixels")))
            }
            _ => Ok(()),
        }
    }
}

crate::names::named_enum! {
    /// How `outline` makes the copy it draws around the selection.
    pub enum OutlineMethod {
        /// Pushed out along its smooth normals by the width in pixels.
        #[default]
        Extrude = "extrude",
        /// Scaled up about its centre (the document's way), so that its bounding sphere grows by
        /// the width in pixels.
        Scale = "scale",
    }
}

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CartoonOptions {
    /// Objects to outline (`outline`); empty: the scene's first shadow caster, else its first object.
    pub select: Vec<String>,
    pub silhouette: SilhouetteMethod,
    /// Edges whose faces fold by more than this many degrees are creases.
    pub crease_deg: f32,
    /// Ink line width in pixels (edges), and the width of the hull rim.
    pub line_width: f32,
    /// Per edge class (silhouette, crease, boundary; see `INK_STYLE_FLAGS`): width and colour
    /// over `line_width` and the default ink. The methods that only find silhouettes use the
    /// silhouette's.
    pub ink: [InkStyle; 3],
    /// Which attribute seams are boundaries (edges method).
    pub seams: Seams,
    /// Faces filled with the background colour, ink on top (the seed's figure 5.1.1, middle).
    pub ink_only: bool,
    /// Outline width in pixels (`outline`).
    pub outline_width: f32,
    /// `alpha-test` ink: pixels whose N.V is at most this are ink (0: a hairline; larger:
    /// thicker lines).
    pub alpha_ref: f32,
    /// Outline colour, 8-bit RGB (so every path writes the same bytes).
    pub outline_colour: [u8; 3],
    /// How the outline copy is made (`outline`).
    pub outline_method: OutlineMethod,
    /// Blur radius of the outline in pixels, 0 for a sharp outline (`outline`).
    pub outline_blur: u32,
}

/// The largest `--outline-blur` radius, in pixels.
pub const MAX_OUTLINE_BLUR: u32 = 16;

impl Default for CartoonOptions {
    fn default() -> Self {
        CartoonOptions {
            select: Vec::new(),
            silhouette: SilhouetteMethod::Edges,
            crease_deg: 40.0,
            line_width: 2.0,
            ink: [InkStyle::default(); 3],
            ink_only: false,
            seams: Seams::default(),
            outline_width: 4.0,
            alpha_ref: 0.3,
            outline_colour: [255, 160, 0],
            outline_method: OutlineMethod::Extrude,
            outline_blur: 0,
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
        if self.outline_blur > MAX_OUTLINE_BLUR {
            return Err(Error::InvalidInput(format!(
                "--outline-blur {}: use 0 (sharp) to {MAX_OUTLINE_BLUR} pixels",
                self.outline_blur
            )));
        }
        for (style, flag) in self.ink.iter().zip(INK_STYLE_FLAGS) {
            style.check(flag)?;
        }
        if !(self.alpha_ref.is_finite() && (0.0..=1.0).contains(&self.alpha_ref)) {
            return Err(Error::InvalidInput(format!("--alpha-ref {}: use 0 to 1 (N.V)", self.alpha_ref)));
        }
        if !(self.crease_deg.is_finite() && (0.0..=180.0).contains(&self.crease_deg)) {
            return Err(Error::InvalidInput(format!("--crease-angle {}: use 0 to 180 degrees", self.crease_deg)));
        }
        Ok(())
    }

    /// The width of edge class `class` (0 silhouette, 1 crease, 2 boundary) in pixels.
    pub fn ink_width(&self, class: usize) -> f32 {
        self.ink.get(class).and_then(|s| s.width).unwrap_or(self.line_width)
    }

    /// Parses `--select NAME,NAME,...` (empty: the default selection).
    pub fn parse_select(text: &str) -> Vec<String> {
        text.split(',').map(str::trim).filter(|s| !s.is_empty()).map(str::to_owned).collect()
    }
}

/// Parses an 8-bit RGB colour written `#RRGGBB` (the `#` optional) for the option `what`.
pub fn parse_rgb_hex(what: &str, text: &str) -> Result<[u8; 3]> {
    let bad = || Error::InvalidInput(format!("{what} '{text}': expected #RRGGBB, six hex digits such as #FFA000"));
    let digits = text.trim().strip_prefix('#').unwrap_or(text.trim());
    if digits.len() != 6 || !digits.chars().all(|c| c.is_ascii_hexdigit()) {
        return Err(bad());
    }
    let byte = |i: usize| u8::from_str_radix(&digits[i..i + 2], 16).map_err(|_| bad());
    Ok([byte(0)?, byte(2)?, byte(4)?])
}

/// Which of the two seed 004 shadow techniques a renderer draws. Not a command-line value
/// (the technique is): JSON keeps its short spelling, `name()` is the technique's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ShadowKind {
    /// Shadow textures baked into each model's atlas (the paper's method).
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
    /// `--light`: whether the light turns from frame to frame.
    pub enum LightMode {
        /// Turns about the vertical by a small step a frame: every frame re-bakes.
        Moving = "moving",
        /// Stays put: after the first frame the shadow map and bake are skipped.
        #[default]
        Fixed = "fixed",
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

impl ShadowVolumeOptions {
    /// Checks the numbers a user typed (k in 1..=8).
    pub fn check(&self) -> Result<()> {
        alpha_counter::check_increment(self.increment).map(|_| ())
    }

    /// The shadowed colour's factor per channel (R, G, B), in 1/255: the tint, else D on all.
    pub fn shadow_rgb(&self) -> [u8; 3] {
        self.shadow_colour.unwrap_or([self.shadow_factor; 3])
    }

    /// The darkest factor: what the blend-only normalisation must bring every count to.
    pub fn darkest(&self) -> u8 {
        self.shadow_rgb().into_iter().min().unwrap_or(self.shadow_factor)
    }
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
    fn rgb_hex_parses_six_digits_and_names_bad_input() {
        assert_eq!(parse_rgb_hex("--c", "#FFa000").ok(), Some([255, 160, 0]));
        assert_eq!(parse_rgb_hex("--c", "0a141e").ok(), Some([10, 20, 30]));
        for bad in ["", "#", "#FFF", "#FFA0000", "#GG0000", "red", "#+1+2+3", "#ÿÿÿ"] {
            let error = parse_rgb_hex("--c", bad).err().map(|e| e.to_string()).unwrap_or_default();
            assert!(error.contains("--c") && error.contains("#RRGGBB"), "{bad:?}: {error}");
        }
    }
}
