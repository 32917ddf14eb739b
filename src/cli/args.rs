//! Command-line arguments. Options shared by `render`, `profile` and later subcommands live in
//! `FrameArgs`, so each new technique slots in as a `--technique` value and its own options.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::mobile_profile;
use crate::gpu::validation::ValidationChecks;
use crate::technique::options::parse_rgb_hex;
use crate::technique::registry::DEFAULT_TECHNIQUE;
use crate::technique::{LightMode, Normalize, OutlineMethod, SilhouetteMethod, TextureShadowOn, VolumeMethod};

#[derive(Debug, Parser)]
#[command(
    name = "nostencil",
    version,
    about = "Stencil effects without a stencil buffer: a Vulkan renderer for mobile-class limits"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render one frame offscreen and write it as PNG.
    Render {
        #[command(flatten)]
        frame: FrameArgs,
        /// Output PNG file (written atomically: no partial file on failure).
        #[arg(long, value_name = "FILE.png")]
        out: PathBuf,
        /// Keep the alpha channel (the emulated stencil) in the PNG instead of writing RGB.
        #[arg(long)]
        keep_alpha: bool,
        /// Record none of the per-pass queries that time and count each pass: for running under
        /// a tool that measures render passes with queries of its own (`profile-app`), which then
        /// measures the frame by itself. The image is the same.
        #[arg(long)]
        no_queries: bool,
    },
    /// Render one frame and report per-pass fill-rate counters.
    Profile {
        #[command(flatten)]
        frame: FrameArgs,
        #[arg(long, value_enum, default_value_t = FormatArg::Table)]
        format: FormatArg,
        /// Variants side by side: `emulated`, `reference`, and for shadow-volume `seed`, `max`,
        /// `subpass` (e.g. `--compare reference,seed,max,subpass`).
        #[arg(long, value_name = "A,B,...", value_delimiter = ',')]
        compare: Vec<String>,
        /// Also write an overdraw heat map (fragments shaded per pixel, counted in alpha).
        #[arg(long, value_name = "FILE.png")]
        heatmap: Option<PathBuf>,
        /// Also write a per-pass bar chart.
        #[arg(long, value_name = "FILE.svg")]
        chart: Option<PathBuf>,
        /// Compare deterministic counters with a budget file; exit 1 naming every pass over it.
        #[arg(long, value_name = "FILE.json")]
        budget: Option<PathBuf>,
        /// Record this frame's deterministic counters as a budget file.
        #[arg(long, value_name = "FILE.json")]
        write_budget: Option<PathBuf>,
    },
    /// Run any Vulkan program under the fill-rate layer (VK_LAYER_NOSTENCIL_fillrate) and report
    /// its render pass instances: draws, fragments, samples passed, overdraw, GPU time, tile
    /// traffic, per frame and aggregated (`nostencil profile-app --frames 10 -- vkcube --c 10`).
    #[command(after_help = crate::cli::profile_app::AFTER_HELP)]
    ProfileApp {
        /// Measure the first N frames (presents), then end the program (SIGTERM, SIGKILL 5 s
        /// later) and report. Default: every frame until the program exits (the report keeps the
        /// last 64, the aggregate covers all).
        #[arg(long, value_name = "N")]
        frames: Option<u32>,
        /// With --frames: leave the program running after N frames; report when it exits.
        #[arg(long)]
        keep_running: bool,
        /// End the program after S seconds (SIGTERM, SIGKILL 5 s later) and report.
        #[arg(long, value_name = "S")]
        seconds: Option<f64>,
        /// Also count each draw of a measured render pass on its own (fragments, samples, GPU
        /// time; JSON `per_draw`, summing to the pass's counters). At most 256 draws a pass.
        #[arg(long)]
        per_draw: bool,
        #[arg(long, value_enum, default_value_t = FormatArg::Table)]
        format: FormatArg,
        /// Compare each render pass's draws, samples passed and fragment invocations (the most
        /// over the measured frames) with a budget from `--record-budget`; exit 1 naming every
        /// render pass over it.
        #[arg(long, value_name = "FILE.json")]
        budget: Option<PathBuf>,
        /// Record this run's counters (per render pass, the most over the measured frames) as
        /// a budget file.
        #[arg(long, value_name = "FILE.json")]
        record_budget: Option<PathBuf>,
        /// Also write a bar chart of the render passes (mean over frames).
        #[arg(long, value_name = "FILE.svg")]
        chart: Option<PathBuf>,
        /// Write the report (in --format) to FILE instead of stdout, which stays the program's.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
        /// The program and its arguments, after `--`.
        #[arg(last = true, value_name = "COMMAND ARGS")]
        command: Vec<String>,
    },
    /// Install or remove the fill-rate layer for this user, so that
    /// `VK_INSTANCE_LAYERS=VK_LAYER_NOSTENCIL_fillrate NOSTENCIL_FILLRATE_OUT=report.json PROGRAM`
    /// works without profile-app.
    Layer {
        #[command(subcommand)]
        action: LayerAction,
    },
    /// Print every pass of a technique with its fixed-function state, as a Markdown table.
    Passes {
        #[arg(long, default_value = DEFAULT_TECHNIQUE)]
        technique: String,
        /// shadow-volume: list only this normalisation path; all by default.
        #[arg(long, value_enum)]
        normalize: Option<Normalize>,
        /// shadow-volume: alpha added per volume wall, in 1/255 steps (1..=8).
        #[arg(long, default_value_t = 1, value_name = "K")]
        increment: u8,
        /// shadow-volume and planar: shadowed colour = colour x F/255; for shadow volumes the
        /// normalisation's iteration count follows it.
        #[arg(long, default_value_t = 102, value_name = "F")]
        shadow_factor: u8,
        /// shadow-volume: a tinted shadow's factors (`#RRGGBB`): the blend-only paths add a
        /// darkness step and an apply per distinct factor.
        #[arg(long, value_name = "#RRGGBB", value_parser = parse_rgb8, conflicts_with = "shadow_factor")]
        shadow_colour: Option<[u8; 3]>,
    },
    /// Time frames of a technique's variants (the real-stencil reference first) in one run.
    Bench {
        #[command(flatten)]
        frame: FrameArgs,
        /// Rounds rendered and discarded before timing (shader compilation); a round is one
        /// frame of each variant.
        #[arg(long, default_value_t = 3)]
        warmup: u32,
        /// Timed rounds: one frame of each variant per round, in turn [default: 150, enough for
        /// the 95% interval of the shadow-volume subpass ratio to stay within +-5% at 1280x720 on
        /// 2 cores; seed 004's Table 1: 10, its atlas-125 rows take seconds a frame].
        #[arg(long)]
        runs: Option<u32>,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
        /// shadow-texture-atlas only: also record seed 004's Table 1 (measured beside the
        /// paper's values) as DIR/table1.json and DIR/table1.md.
        #[arg(long, value_name = "DIR")]
        table1_out: Option<PathBuf>,
        /// shadow-texture-atlas or shadow-map only: instead of timing, count the pixels of
        /// --scene that flicker over STEPS neighbouring light angles, shadow texture (mips)
        /// against shadow map (seed 004's figures 6 and 7; use a small --size to minify).
        #[arg(long, value_name = "STEPS", num_args = 0..=1, default_missing_value = "12")]
        mip_flicker: Option<u32>,
    },
    /// Bake one model's shadow texture (shadow-texture-atlas) and write it as PNG.
    Bake {
        #[command(flatten)]
        frame: FrameArgs,
        /// Object to bake, by name (default: the first that casts shadows, else the first).
        #[arg(long, value_name = "NAME")]
        model: Option<String>,
        /// Mip level to write.
        #[arg(long, default_value_t = 0)]
        mip: u32,
        /// Output PNG file (written atomically).
        #[arg(long, value_name = "FILE.png")]
        out: PathBuf,
    },
    /// Show the scene in a window, every technique switchable live (keys: `nostencil view
    /// --help`). The window's size is the frame's.
    // The key list comes from the viewer's key map, the table its key handler reads.
    #[command(after_help = crate::viewer::keys::help())]
    View {
        #[command(flatten)]
        frame: FrameArgs,
        /// Render this many frames, then exit (with --screenshot: save the last one first).
        #[arg(long, value_name = "N")]
        frames: Option<u32>,
        /// Save the last presented image as an RGB PNG (atomic write); needs --frames.
        #[arg(long, value_name = "FILE.png")]
        screenshot: Option<PathBuf>,
        /// After N presented frames, resize the window to WxH (for tests of the resize path).
        #[arg(long, num_args = 2, value_names = ["N", "WxH"])]
        resize_after: Option<Vec<String>>,
        /// After N presented frames, act as if KEY (a letter from the key list) was pressed
        /// (for tests of a live switch, such as M for the sample count).
        #[arg(long, num_args = 2, value_names = ["N", "KEY"])]
        press_after: Option<Vec<String>>,
        /// Start with the animation (casters turning, animated models playing) paused: frames
        /// then match `render`.
        #[arg(long)]
        paused: bool,
        /// Every N presented frames, go to the next stop of a tour of every technique, both
        /// stencil modes and 1x/4x samples, resizing the window at each; after each full tour
        /// print the resident memory and the live Vulkan objects (the soak test).
        #[arg(long, value_name = "N")]
        tour: Option<u32>,
    },
    /// Print the device, the mobile profile, and every limit the device is checked against.
    Info {
        #[command(flatten)]
        gpu: GpuArgs,
        #[arg(long)]
        json: bool,
    },
}

#[derive(Debug, Clone, Args)]
pub struct GpuArgs {
    /// Device by index or name fragment (`lavapipe`); default: NOSTENCIL_DEVICE, else automatic.
    #[arg(long, value_name = "INDEX|NAME")]
    pub device: Option<String>,
    /// Enable the Khronos validation layer (messages go to stderr; `info --validation` lists
    /// them). CHECKS: `all` (the default: core, synchronisation and best practices) or a list of
    /// `core`, `sync`, `best-practices`; core is always on. This layer version's synchronisation
    /// checks keep tens of KiB per frame until exit: a long viewer session may leave them out.
    #[arg(
        long,
        value_name = "CHECKS",
        num_args = 0..=1,
        require_equals = true,
        default_missing_value = "all",
        value_parser = ValidationChecks::parse
    )]
    pub validation: Option<ValidationChecks>,
}

#[derive(Debug, Clone, Args)]
pub struct FrameArgs {
    /// Frame size, WIDTHxHEIGHT, each side 1..=4096 (the mobile profile's limit).
    #[arg(long, value_name = "WxH", default_value = "1280x720", value_parser = parse_size_arg)]
    pub size: (u32, u32),
    /// `emulated` (no stencil aspect: alpha-channel emulation) or `reference` (real stencil).
    #[arg(long, value_enum, default_value_t)]
    pub stencil: StencilMode,
    /// Samples per pixel: 1, 2 (where the device offers it) or 4. 4 is what a mobile port
    /// ships: the samples live in tile memory and only the resolved frame is stored.
    #[arg(long, default_value_t = 4, value_name = "1|2|4")]
    pub samples: u32,
    /// Technique to render (`bench` also takes `all`).
    #[arg(long, default_value = DEFAULT_TECHNIQUE)]
    pub technique: String,
    /// Built-in scene name (see `nostencil info`) or a .gltf/.glb file.
    #[arg(long, default_value = "default")]
    pub scene: String,
    /// Animation time in seconds: a glTF scene's first animation (looping), the built-in character's walk.
    #[arg(long, default_value_t = 0.0, value_name = "SECONDS")]
    pub time: f32,
    /// shadow-volume: alpha added per volume wall, in 1/255 steps (1..=8).
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub increment: u8,
    /// shadow-volume: `auto` (z-fail when the camera is inside a volume), `zpass` or `zfail`.
    #[arg(long, value_enum, default_value_t)]
    pub volume_method: VolumeMethod,
    /// shadow-volume: how counts become a mask.
    #[arg(long, value_enum, default_value_t)]
    pub normalize: Normalize,
    /// shadow-volume: add the full-screen saturation probe, a diagnostic pass (`seed` and `max`
    /// count saturation only with it; `subpass` counts it in its apply, and the probe then
    /// cross-checks that count). Never part of a timed `bench` frame.
    #[arg(long)]
    pub saturation_probe: bool,
    /// shadow-volume: draw every volume whole, to infinity and over the whole frame, instead of
    /// clipped to the receivers' bounds and scissored to where it can shade (to measure what
    /// the clipping saves; the image is the same).
    #[arg(long)]
    pub unclipped_volumes: bool,
    /// outline: objects to outline, by name (default: the scene's first shadow caster).
    #[arg(long, value_name = "NAME,...", default_value = "")]
    pub select: String,
    /// silhouette/toon: how ink is found: `edges` (CPU, screen-space quads), `shader` (N.V rim),
    /// `hull` (inverted hull) or `alpha-test` (N.V per pixel against `--alpha-ref`).
    #[arg(long, value_enum, default_value_t)]
    pub silhouette: SilhouetteMethod,
    /// silhouette/toon: edges whose faces fold by more than this are creases (degrees).
    #[arg(long, default_value_t = 40.0, value_name = "DEG")]
    pub crease_angle: f32,
    /// silhouette/toon: ink line width in pixels (edges and hull).
    #[arg(long, default_value_t = 2.0, value_name = "PX")]
    pub line_width: f32,
    /// silhouette/toon: silhouette ink as WIDTH[,#RRGGBB] (sRGB); default `--line-width` and
    /// the dark ink. The methods other than `edges` draw silhouettes only, in this style.
    #[arg(long, value_name = "WIDTH[,#RRGGBB]")]
    pub ink_silhouette: Option<String>,
    /// silhouette/toon `--silhouette edges`: crease ink as WIDTH[,#RRGGBB].
    #[arg(long, value_name = "WIDTH[,#RRGGBB]")]
    pub ink_crease: Option<String>,
    /// silhouette/toon `--silhouette edges`: boundary ink as WIDTH[,#RRGGBB].
    #[arg(long, value_name = "WIDTH[,#RRGGBB]")]
    pub ink_boundary: Option<String>,
    /// silhouette/toon: faces filled with the background colour, ink on top (the seed's
    /// figure 5.1.1, middle).
    #[arg(long)]
    pub ink_only: bool,
    /// silhouette/toon `--silhouette edges`: attribute seams drawn as boundaries: `normal`, `uv`,
    /// `material` (borders between a glTF mesh's primitives; comma-separated) or `none`.
    #[arg(long, default_value = "normal,material", value_name = "normal,uv,material|none")]
    pub seams: String,
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
    /// outline: outline colour as the PNG shows it, sRGB hex.
    #[arg(long, visible_alias = "outline-color", default_value = "#FFA000", value_name = "#RRGGBB",
          value_parser = parse_colour_arg)]
    pub outline_colour: [u8; 3],
    /// outline: blur the outline by two 1D box passes of this radius in pixels (0..=16; 0: sharp).
    // Negative numbers are values here, so that `-1` is refused as a bad radius, by name.
    #[arg(long, default_value_t = 0, value_name = "PX", allow_negative_numbers = true)]
    pub outline_blur: u32,
    /// shadow-volume, planar, blob, shadow-texture: shadowed colour = colour x F/255 (0..=255;
    /// 255: no shadow). For shadow volumes the normalisation's iteration count follows it.
    #[arg(long, default_value_t = 102, value_name = "F")]
    pub shadow_factor: u8,
    /// shadow-volume: a tinted shadow (seed 000's apply modulates with a shadow colour):
    /// shadowed colour = colour x RR/255, GG/255, BB/255 per channel, linear factors given in hex
    /// (`#RRGGBB` or `RRGGBB`), in every path. Instead of --shadow-factor.
    #[arg(long, value_name = "#RRGGBB", value_parser = parse_rgb8, conflicts_with = "shadow_factor")]
    pub shadow_colour: Option<[u8; 3]>,
    /// planar, shadow-texture, blob: the receiving plane crosses the y axis at H (default: the
    /// lowest flat horizontal non-caster is the ground).
    #[arg(long, value_name = "H", allow_hyphen_values = true)]
    pub plane_height: Option<f32>,
    /// planar, shadow-texture: the receiving plane's normal (any length but zero; default
    /// 0,1,0), projected onto with Blinn's shadow matrix; e.g. `--scene slope --plane-normal 0,3,1`.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub plane_normal: Option<String>,
    /// planar, shadow-texture: cast the shadow from each caster simplified with meshoptimizer
    /// to about this fraction of its triangles (0 < RATIO <= 1; `bench` adds a variant with it).
    #[arg(long, value_name = "RATIO")]
    pub shadow_lod: Option<f32>,
    /// shadow-texture: side of the texture the casters are drawn into from the light, in texels
    /// (the seed's render texture; small on purpose).
    #[arg(long, default_value_t = crate::technique::options::DEFAULT_TEXTURE_SHADOW_SIZE, value_name = "N")]
    pub render_texture_size: u32,
    /// shadow-texture: show the texture on the `receivers` drawn again (clipped to them) or, as
    /// the seed does, on one `quad` on the plane around the casters' shadow.
    #[arg(long, value_enum, default_value_t)]
    pub render_texture_on: TextureShadowOn,
    /// shadow-map, shadow-texture-atlas, projective-texture: `moving` (turns every frame:
    /// re-bake) or `fixed` (after the first frame the shadow map and bake are skipped).
    #[arg(long, value_enum, default_value_t)]
    pub light: LightMode,
    /// shadow-map, shadow-texture-atlas, projective-texture: shadow map side in texels (power of
    /// two; also the projective texture's side).
    #[arg(long, default_value_t = 512, value_name = "N")]
    pub shadow_map_size: u32,
    /// shadow-texture-atlas: shadow texture side for meshes that are not geometry images.
    #[arg(long, default_value_t = 256, value_name = "N")]
    pub shadow_texture_size: u32,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// `nostencil layer ...`.
#[derive(Debug, Subcommand)]
pub enum LayerAction {
    /// Copy libnostencil.so to ~/.local/lib/nostencil/ and write its manifest to
    /// $XDG_DATA_HOME/vulkan/explicit_layer.d/ (default ~/.local/share/...).
    Install {
        /// The layer library to install; default: the one built beside this executable.
        #[arg(long, value_name = "PATH")]
        library: Option<PathBuf>,
    },
    /// Remove what `layer install` wrote.
    Uninstall,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FormatArg {
    Table,
    Json,
    Csv,
}

/// Parses `WIDTHxHEIGHT` and checks it against the mobile profile.
pub fn parse_size(text: &str) -> Result<(u32, u32)> {
    let bad = || Error::InvalidInput(format!("size '{text}': expected WIDTHxHEIGHT, such as 1280x720"));
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let width: u32 = w.trim().parse().map_err(|_| bad())?;
    let height: u32 = h.trim().parse().map_err(|_| bad())?;
    mobile_profile::check_image_size("frame", width, height)?;
    Ok((width, height))
}

fn parse_colour_arg(text: &str) -> std::result::Result<[u8; 3], String> {
    // clap names the option and the value already.
    parse_rgb_hex("--outline-colour", text).map_err(|_| "expected six hex digits, such as #FFA000".to_string())
}

fn parse_size_arg(text: &str) -> std::result::Result<(u32, u32), String> {
    parse_size(text).map_err(|e| e.to_string())
}

/// `#RRGGBB` or `RRGGBB` as three bytes, for clap (the one parser is `parse_rgb_hex`).
fn parse_rgb8(text: &str) -> Result<[u8; 3], String> {
    parse_rgb_hex("colour", text).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_are_checked() {
        assert_eq!(parse_size("256x128").ok(), Some((256, 128)));
        assert!(parse_size("0x256").is_err());
        assert!(parse_size("5000x256").is_err());
        assert!(parse_size("256").is_err());
        assert!(parse_size("axb").is_err());
    }
}
