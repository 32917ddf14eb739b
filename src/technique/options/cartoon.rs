//! The cartoon family's options (outline, silhouette, toon), as plain data and as their own
//! flags (`clap::Args`, flattened into the command line).

use crate::error::{Error, Result};
use crate::technique::flags::{clap_defaults, parse_rgb_hex};

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_the_flags_defaults() {
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
    }

    #[test]
    fn seams_print_as_they_parse() {
        for text in ["normal,material", "none", "uv", "normal,uv,material"] {
            assert_eq!(Seams::parse(text).map(|s| s.to_string()).ok().as_deref(), Some(text));
        }
    }
}
