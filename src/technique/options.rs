//! The options of each technique family, as plain data and as their own flags (`clap::Args`,
//! flattened into the command line): what the command line, the viewer and
//! a port set. (Which technique, the size and the stencil path are in `RenderOptions`, beside
//! the `Technique` interface.)

use clap::ArgAction;

use super::alpha_counter;
use crate::error::{Error, Result};

/// What a family's options are when no flag is given: its `Default`. The defaults are written
/// once, on the flags of its `clap::Args` struct (where `--help` shows them).
pub(crate) fn clap_defaults<T: clap::Args + clap::FromArgMatches>() -> T {
    let command = T::augment_args(clap::Command::new("defaults").no_binary_name(true));
    match command.try_get_matches_from(std::iter::empty::<&str>()).and_then(|m| T::from_arg_matches(&m)) {
        Ok(options) => options,
        // The flags' own defaults, not user input: a unit test parses each family's.
        Err(e) => panic!("the defaults of {} do not parse: {e}", std::any::type_name::<T>()),
    }
}

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

crate::names::named_enum! {
    /// How the count becomes a shadow mask.
    pub enum Normalize {
        /// Seed 000's fixed-function sequence (Hall's article, docs/sources.md): N0, iterations,
        /// REVERSE_SUBTRACT D, ADD D, apply.
        #[default]
        Seed = "seed",
        /// As `seed`, with one MAX pass in place of the two D passes.
        Max = "max",
        /// One full-screen pass reading the count as an input attachment.
        Subpass = "subpass",
    }
}

/// The shadow-volume family's options (`shadow-volume`), and its flags. How dark the shadow is
/// is `RenderOptions::shadow_tone`, shared with the planar family.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, clap::Args)]
pub struct ShadowVolumeOptions {
    // k: each volume wall adds or removes k/255 of alpha.
    /// shadow-volume: alpha added per volume wall, in 1/255 steps (1..=8).
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub increment: u8,
    /// shadow-volume: `auto` (z-fail when the camera is inside a volume), `zpass` or `zfail`.
    #[arg(id = "volume_method", long = "volume-method", value_name = "VOLUME_METHOD", value_enum, default_value_t)]
    pub method: VolumeMethod,
    /// shadow-volume: how counts become a mask.
    #[arg(long, value_enum, default_value_t)]
    pub normalize: Normalize,
    // A diagnostic pass a user asks for (docs/design/saturation.md), never part of a timed frame.
    /// shadow-volume: add the full-screen saturation probe, a diagnostic pass (`seed` and `max`
    /// count saturation only with it; `subpass` counts it in its apply, and the probe then
    /// cross-checks that count). Never part of a timed `bench` frame.
    #[arg(long)]
    pub saturation_probe: bool,
    // Volumes end just past the receivers' bounds and each is scissored to where it can shade,
    // the apply to their union, in both paths alike (docs/shadow-volumes.md, "Volumes clipped to
    // where they can shade"). Off (`--unclipped-volumes`): every volume reaches infinity over
    // the whole frame, to measure what clipping saves.
    /// shadow-volume: draw every volume whole, to infinity and over the whole frame, instead of
    /// clipped to the receivers' bounds and scissored to where it can shade (to measure what
    /// the clipping saves; the image is the same).
    #[arg(id = "unclipped_volumes", long = "unclipped-volumes", action = ArgAction::SetFalse)]
    pub clip_volumes: bool,
    // A caster wholly in the shadow of other casters, as the light sees it, casts nothing new
    // (CC Shadow Volumes' culling, made conservative: docs/shadow-volumes.md, "Casters culled").
    // Opt-in: on real assemblies it finds few casters for its CPU cost (measured there).
    /// shadow-volume: leave out, per light, the volumes of casters that lie wholly in the shadow
    /// of other casters, found on the CPU from a conservative occluder map (the image is the
    /// same; `profile` reports the casters culled and the CPU time).
    #[arg(long = "cull-casters")]
    pub cull_casters: bool,
    /// Draw the volumes of this caster only (its index among the frame's casters,
    /// `technique_stats.casters`): how `profile --caster-fill` measures each caster's share of
    /// the fill, frame by frame. Never set by a user.
    #[arg(skip)]
    pub only_caster: Option<u32>,
    /// The device has `fragmentStoresAndAtomics` (Android Baseline 2022), so the `subpass`
    /// apply counts saturated samples with one atomic add per pixel. The renderer turns it off on a
    /// device without the feature; a plan printed without a device assumes the baseline.
    #[arg(skip = true)]
    pub fragment_atomics: bool,
}

impl Default for ShadowVolumeOptions {
    fn default() -> Self {
        clap_defaults()
    }
}

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
        Seams::parse_value(text).map_err(|why| Error::InvalidInput(format!("--seams {why}")))
    }

    /// `parse` for clap, which names the option and the value.
    fn parse_value(text: &str) -> std::result::Result<Seams, String> {
        let mut seams = Seams { normal: false, uv: false, material: false };
        for word in text.split(',').map(str::trim) {
            match word {
                "normal" => seams.normal = true,
                "uv" => seams.uv = true,
                "material" => seams.material = true,
                "none" | "" => {}
                other => return Err(format!("'{other}': use normal, uv, material or none, comma-separated")),
            }
        }
        Ok(seams)
    }
}

impl std::fmt::Display for Seams {
    /// As `--seams` takes it (`normal,material`, or `none`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let words: Vec<&str> = [(self.normal, "normal"), (self.uv, "uv"), (self.material, "material")]
            .into_iter()
            .filter_map(|(on, word)| on.then_some(word))
            .collect();
        if words.is_empty() {
            f.write_str("none")
        } else {
            f.write_str(&words.join(","))
        }
    }
}

/// The command-line flag of each edge class's style, in the order of `CartoonOptions::ink`.
pub const INK_STYLE_FLAGS: [&str; 3] = ["--ink-silhouette", "--ink-crease", "--ink-boundary"];

impl InkStyle {
    /// Parses `WIDTH`, `WIDTH,#RRGGBB` or `#RRGGBB` (the `#` is optional), for `flag`.
    pub fn parse(flag: &str, text: &str) -> Result<InkStyle> {
        InkStyle::parse_value(text).map_err(|why| Error::InvalidInput(format!("{flag} '{text}': {why}")))
    }

    /// `parse` for clap, which names the option and the value.
    fn parse_value(text: &str) -> std::result::Result<InkStyle, String> {
        let bad = |why: &str| format!("{why}; expected WIDTH[,#RRGGBB]");
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
        match style.width {
            Some(w) if !(w.is_finite() && (0.5..=64.0).contains(&w)) => Err(format!("width {w}: use 0.5 to 64 pixels")),
            _ => Ok(style),
        }
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

/// Each edge class's ink (`--ink-silhouette`, `--ink-crease`, `--ink-boundary`); `None`: the
/// default style (`--line-width`, the dark ink).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, clap::Args)]
// The fields' comments are `--help` text, where WIDTH[,#RRGGBB] is the usage, not a link.
#[allow(rustdoc::broken_intra_doc_links)]
pub struct InkStyles {
    /// silhouette/toon: silhouette ink as WIDTH[,#RRGGBB] (sRGB); default `--line-width` and
    /// the dark ink. The methods other than `edges` draw silhouettes only, in this style.
    #[arg(id = "ink_silhouette", long = "ink-silhouette", value_name = "WIDTH[,#RRGGBB]", value_parser = InkStyle::parse_value)]
    pub silhouette: Option<InkStyle>,
    /// silhouette/toon `--silhouette edges`: crease ink as WIDTH[,#RRGGBB].
    #[arg(id = "ink_crease", long = "ink-crease", value_name = "WIDTH[,#RRGGBB]", value_parser = InkStyle::parse_value)]
    pub crease: Option<InkStyle>,
    /// silhouette/toon `--silhouette edges`: boundary ink as WIDTH[,#RRGGBB].
    #[arg(id = "ink_boundary", long = "ink-boundary", value_name = "WIDTH[,#RRGGBB]", value_parser = InkStyle::parse_value)]
    pub boundary: Option<InkStyle>,
}

impl InkStyles {
    /// Edge class `class`'s style (0 silhouette, 1 crease, 2 boundary, as `INK_STYLE_FLAGS`).
    pub fn get(&self, class: usize) -> InkStyle {
        [self.silhouette, self.crease, self.boundary].get(class).copied().flatten().unwrap_or_default()
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

/// The cartoon family's options (`outline`, `silhouette`, `toon`), and their flags.
#[derive(Debug, Clone, PartialEq, serde::Serialize, clap::Args)]
pub struct CartoonOptions {
    /// outline: objects to outline, by name (default: the scene's first shadow caster).
    #[arg(long, value_name = "NAME,...", value_delimiter = ',', value_parser = parse_object_name)]
    pub select: Vec<String>,
    /// silhouette/toon: how ink is found: `edges` (CPU, screen-space quads), `shader` (N.V rim),
    /// `hull` (inverted hull) or `alpha-test` (N.V per pixel against `--alpha-ref`).
    #[arg(long, value_enum, default_value_t)]
    pub silhouette: SilhouetteMethod,
    /// silhouette/toon: edges whose faces fold by more than this are creases (degrees).
    #[arg(id = "crease_angle", long = "crease-angle", default_value_t = 40.0, value_name = "DEG")]
    pub crease_deg: f32,
    /// silhouette/toon: ink line width in pixels (edges and hull).
    #[arg(long, default_value_t = 2.0, value_name = "PX")]
    pub line_width: f32,
    // Per edge class: width and colour over `line_width` and the default ink. The methods that
    // only find silhouettes use the silhouette's.
    #[command(flatten)]
    pub ink: InkStyles,
    /// silhouette/toon: faces filled with the background colour, ink on top (the seed's
    /// figure 5.1.1, middle).
    #[arg(long)]
    pub ink_only: bool,
    /// silhouette/toon `--silhouette edges`: attribute seams drawn as boundaries: `normal`, `uv`,
    /// `material` (borders between a glTF mesh's primitives; comma-separated) or `none`.
    #[arg(
        long,
        default_value_t = Seams::default(),
        value_name = "normal,uv,material|none",
        value_parser = Seams::parse_value
    )]
    pub seams: Seams,
    /// silhouette/toon `--silhouette alpha-test`: pixels with N.V at most this are ink (0..=1;
    /// larger: thicker lines).
    #[arg(long, default_value_t = 0.3, value_name = "N.V")]
    pub alpha_ref: f32,
    /// outline: outline width in pixels (0.5..=64).
    #[arg(long, default_value_t = 4.0, value_name = "PX")]
    pub outline_width: f32,
    /// outline: how the outline copy is made: `extrude` (pushed out along its smooth normals) or
    /// `scale` (scaled up about its centre, as the document does).
    #[arg(long, value_enum, default_value_t)]
    pub outline_method: OutlineMethod,
    // 8-bit RGB, so every path writes the same bytes.
    /// outline: outline colour as the PNG shows it, sRGB hex.
    #[arg(long, visible_alias = "outline-color", default_value = "#FFA000", value_name = "#RRGGBB",
          value_parser = parse_colour_arg)]
    pub outline_colour: [u8; 3],
    /// outline: blur the outline by two 1D box passes of this radius in pixels (0..=16; 0: sharp).
    // Negative numbers are values here, so that `-1` is refused as a bad radius, by name.
    #[arg(long, default_value_t = 0, value_name = "PX", allow_negative_numbers = true)]
    pub outline_blur: u32,
}

/// The largest `--outline-blur` radius, in pixels.
pub const MAX_OUTLINE_BLUR: u32 = 16;

impl Default for CartoonOptions {
    fn default() -> Self {
        clap_defaults()
    }
}

/// `--outline-colour`'s value, for clap (which names the option and the value).
fn parse_colour_arg(text: &str) -> std::result::Result<[u8; 3], String> {
    parse_rgb_hex("--outline-colour", text).map_err(|_| "expected six hex digits, such as #FFA000".to_string())
}

/// One name of `--select NAME,...`, trimmed.
fn parse_object_name(text: &str) -> std::result::Result<String, String> {
    match text.trim() {
        "" => Err("an empty object name; expected NAME,NAME,...".to_owned()),
        name => Ok(name.to_owned()),
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
        for (class, flag) in INK_STYLE_FLAGS.into_iter().enumerate() {
            self.ink.get(class).check(flag)?;
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
        self.ink.get(class).width.unwrap_or(self.line_width)
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

impl ShadowVolumeOptions {
    /// Checks the numbers a user typed (k in 1..=8).
    pub fn check(&self) -> Result<()> {
        alpha_counter::check_increment(self.increment).map(|_| ())
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
    fn every_familys_defaults_are_its_flags_defaults() {
        let volumes = ShadowVolumeOptions::default();
        assert_eq!((volumes.increment, volumes.method, volumes.normalize), (1, VolumeMethod::Auto, Normalize::Seed));
        assert!(volumes.clip_volumes && volumes.fragment_atomics && !volumes.saturation_probe);
        let planar = PlanarOptions::default();
        assert_eq!(planar.plane, None, "no plane flag given: the plane is found");
        assert!(planar.shadows && planar.shadow_lod.is_none());
        assert_eq!((planar.texture_size, planar.texture_on), (DEFAULT_TEXTURE_SHADOW_SIZE, TextureShadowOn::Receivers));
        assert_eq!(GivenPlane::default(), GivenPlane { normal: [0.0, 1.0, 0.0], height: 0.0 });
        let cartoon = CartoonOptions::default();
        assert_eq!(
            (cartoon.outline_colour, cartoon.seams, cartoon.ink),
            ([255, 160, 0], Seams::default(), InkStyles::default())
        );
        assert_eq!(
            (cartoon.crease_deg, cartoon.line_width, cartoon.outline_width, cartoon.alpha_ref),
            (40.0, 2.0, 4.0, 0.3)
        );
        assert!(cartoon.select.is_empty());
        let atlas = ShadowAtlasOptions::default();
        assert_eq!((atlas.map_size, atlas.texture_size, atlas.light), (512, 256, LightMode::Fixed));
    }

    #[test]
    fn seams_print_as_they_parse() {
        for text in ["normal,material", "none", "uv", "normal,uv,material"] {
            assert_eq!(Seams::parse(text).map(|s| s.to_string()).ok().as_deref(), Some(text));
        }
    }

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
