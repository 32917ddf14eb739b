//! Command-line arguments. Options shared by `render`, `profile` and later subcommands live in
//! `FrameArgs`, so each new technique slots in as a `--technique` value; a technique family's
//! own options are its options struct (`clap::Args`, in `technique`), flattened here.

use std::path::PathBuf;

use clap::parser::ValueSource;
use clap::{ArgMatches, Args, FromArgMatches, Parser, Subcommand, ValueEnum};

use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::mobile_profile;
use crate::gpu::validation::ValidationChecks;
use crate::render::Skinning;
use crate::scene::SceneLight;
use crate::technique::registry::DEFAULT_TECHNIQUE;
use crate::technique::{
    CartoonOptions, Normalize, PlanarOptions, ShadowAtlasOptions, ShadowVolumeOptions, SharedShadowArgs, VolumeMethod,
};
use crate::viewer::PresentPath;

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
        /// Also write the frame on a timeline: Chrome trace-event JSON (ui.perfetto.dev,
        /// chrome://tracing) with a GPU track (a slice per pass), the CPU's record, submit and
        /// wait, and counter tracks (fragments, samples, bytes).
        #[arg(long, value_name = "FILE.json")]
        trace: Option<PathBuf>,
        /// Record this frame's deterministic counters as a budget file (`--write-budget`, its
        /// old name, still works).
        #[arg(long, value_name = "FILE.json", alias = "write-budget")]
        record_budget: Option<PathBuf>,
        #[command(flatten)]
        page: PageArgs,
        /// Profile the frame in which object NAME has just moved (a step of 1% of the scene's
        /// size along x), the light and every other object still: shadow-texture-atlas then
        /// re-bakes only the shadow textures that model can change.
        #[arg(long, value_name = "NAME")]
        move_model: Option<String>,
        /// shadow-volume: also measure each caster's volumes alone (a frame per caster, the
        /// same counters) and list the N casters that spend most of the volume fill.
        #[arg(long, value_name = "N", num_args = 0..=1, default_missing_value = "10",
              value_parser = clap::value_parser!(u32).range(1..))]
        caster_fill: Option<u32>,
    },
    /// Run any Vulkan program under the fill-rate layer (VK_LAYER_NOSTENCIL_fillrate) and report
    /// its render pass instances: draws, fragments, samples passed, overdraw, GPU time, tile
    /// traffic; and its dispatches and transfers: invocations, workgroups, bytes, GPU time; per
    /// frame and aggregated (`nostencil profile-app --frames 10 -- vkcube --c 10`).
    #[command(after_help = crate::cli::profile_app::AFTER_HELP)]
    ProfileApp {
        /// Measure the first N frames (see --frame-on), then end the program (SIGTERM, SIGKILL 5 s
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
        /// Check the load/store ops as a tile-based GPU would (NOSTENCIL_FILLRATE_TILER=1): fill
        /// what a tiler would not keep (DONT_CARE loads and stores) with a magenta and green
        /// pattern, and flag, by pass and attachment, multisampled stores, vkCmdResolveImage,
        /// transient images used outside their pass, outputs stored and never read or
        /// overwritten unread, dead passes, and LOADs of what a pass left DONT_CARE. Exit 1 on
        /// any flag.
        #[arg(long)]
        tiler_check: bool,
        /// What ends a frame when the program does not mark frames with VK_EXT_frame_boundary:
        /// a present (default; with --gl, a swap), every queue submission, every host wait (a
        /// fence, vkQueueWaitIdle, vkDeviceWaitIdle, a timeline semaphore), or every GL buffer
        /// swap (glXSwapBuffers, eglSwapBuffers; --gl only). Submit and wait are for programs
        /// that never present, such as a headless filter.
        #[arg(long, value_enum)]
        frame_on: Option<FrameOnArg>,
        /// The program is an OpenGL or OpenGL ES program: run it on Vulkan through Mesa's zink
        /// (on lavapipe: LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=zink), with the layer's library
        /// preloaded so that its buffer swaps end frames (docs/fillrate-layer.md, "OpenGL and
        /// GLES programs").
        #[arg(long)]
        gl: bool,
        /// With --gl: the Vulkan device zink runs the program on, by index or name (`lavapipe`
        /// for the CPU's) [default: NOSTENCIL_DEVICE, else a GPU if there is one, else
        /// lavapipe]. A Vulkan program chooses its own device.
        #[arg(long, value_name = "INDEX|NAME", requires = "gl")]
        device: Option<String>,
        #[arg(long, value_enum, default_value_t = FormatArg::Table)]
        format: FormatArg,
        /// Compare each render pass's draws, samples passed and fragment invocations (the most
        /// over the measured frames) with a budget from `--record-budget`; exit 1 naming every
        /// render pass over it.
        #[arg(long, value_name = "FILE.json")]
        budget: Option<PathBuf>,
        /// Record this run's counters (per render pass, the most over the measured frames) as
        /// a budget file (`--write-budget`, `profile`'s old name for it, works too).
        #[arg(long, value_name = "FILE.json", alias = "write-budget")]
        record_budget: Option<PathBuf>,
        #[command(flatten)]
        page: PageArgs,
        /// Also write a bar chart of the render passes (mean over frames).
        #[arg(long, value_name = "FILE.svg")]
        chart: Option<PathBuf>,
        /// Also write the measured frames on a timeline: Chrome trace-event JSON
        /// (ui.perfetto.dev, chrome://tracing), a GPU track with each pass's GPU time laid end to
        /// end and counter tracks per frame (fragments, samples, bytes).
        #[arg(long, value_name = "FILE.json")]
        trace: Option<PathBuf>,
        /// Write the report (in --format) to FILE instead of stdout, which stays the program's.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
        /// Write the image the program presents at the end of frame --capture-frame as an RGB
        /// PNG (NOSTENCIL_FILLRATE_CAPTURE): the layer copies the presented swapchain image (8-bit
        /// RGBA or BGRA). Exit 1 if no image was captured.
        #[arg(long, value_name = "FILE.png")]
        capture: Option<PathBuf>,
        /// The frame whose presented image --capture writes, from 0 (the report's frame index).
        #[arg(long, value_name = "N", requires = "capture", default_value_t = 0)]
        capture_frame: u64,
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
        /// Plan for this scene's lights (a built-in scene or a .gltf/.glb file): the additive
        /// loop has passes per light.
        #[arg(long, default_value = "default")]
        scene: String,
        /// Adds a light to the scene's, as for `render` (repeatable).
        #[arg(long = "light", value_name = "SPEC", value_parser = parse_light_arg)]
        lights: Vec<SceneLight>,
        /// The --light lights replace the scene's.
        #[arg(long, requires = "lights")]
        replace_lights: bool,
        /// Samples per pixel the plans are for, as `render --samples` (some passes differ: a
        /// shadow-volume `subpass` frame reads its count in the shading pass at one sample).
        #[arg(long, default_value_t = 4, value_name = "1|2|4")]
        samples: u32,
        #[command(flatten)]
        plans: PassesArgs,
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
        /// Print JSON instead of a table (`--format json` says the same, as `profile` says it).
        #[arg(long)]
        json: bool,
        /// table (default) or json, as `profile` and `profile-app` take it.
        #[arg(long, value_enum)]
        format: Option<FormatArg>,
        /// Also write one self-contained HTML page of the run: each variant's frame time with
        /// its interval and its ratio to the first, and the JSON report embedded.
        #[arg(long, value_name = "FILE.html")]
        html: Option<PathBuf>,
        /// Also write every frame rendered (warm-up ones too) on a timeline: Chrome trace-event
        /// JSON (ui.perfetto.dev, chrome://tracing) with GPU, CPU and counter tracks.
        #[arg(long, value_name = "FILE.json")]
        trace: Option<PathBuf>,
        /// shadow-texture-atlas only: also record seed 004's Table 1 (measured beside the
        /// paper's values) as DIR/table1.json and DIR/table1.md.
        #[arg(long, value_name = "DIR")]
        table1_out: Option<PathBuf>,
        /// shadow-texture-atlas or shadow-map only: instead of timing, count the pixels of
        /// --scene that flicker over STEPS neighbouring light angles, shadow texture (mips)
        /// against shadow map (seed 004's figures 6 and 7; use a small --size to minify).
        #[arg(long, value_name = "STEPS", num_args = 0..=1, default_missing_value = "12")]
        mip_flicker: Option<u32>,
        /// Instead of timing single frames: play N frames of each technique (`--technique` one,
        /// a list, or all) as a game's loop does, the scene animated as in the viewer, frames
        /// kept on the GPU, the techniques in turn; report frames per second (and its ratio to
        /// the first technique), the render thread's CPU ms a frame and its jobs' on other cores
        /// (shadow volumes), and the memory allocations, buffers and fence waits a frame makes.
        #[arg(long = "loop", value_name = "N")]
        frame_loop: Option<u32>,
        /// With --loop: frames each technique keeps in flight (1 to 3): a frame is submitted
        /// without waiting for the one before. Each technique then plays turns of 8 frames,
        /// its frames in flight finished at the end of each turn, the turn timed whole.
        /// Techniques whose per-frame data is not kept per frame slot play one at a time.
        #[arg(long, value_name = "N", default_value_t = 2, requires = "frame_loop",
              value_parser = clap::value_parser!(u32).range(1..=3))]
        frames_in_flight: u32,
        /// With --loop: play shadow-volume once per volume extrusion (`indices` and `shader`),
        /// in turn with the others, to compare their costs in one run.
        #[arg(long)]
        each_extrusion: bool,
        /// With --loop: play each technique once skinning on the GPU and once on the CPU
        /// (`--skinning`), in turn, to compare their costs in one run (the `skinning` column
        /// says where each one skinned).
        #[arg(long, requires = "frame_loop")]
        each_skinning: bool,
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
        #[command(flatten)]
        script: ViewScript,
        /// Start with the animation (casters turning, animated models playing) paused: frames
        /// then match `render`.
        #[arg(long)]
        paused: bool,
        /// Every N presented frames, go to the next stop of a tour of every technique, both
        /// stencil modes and 1x/4x samples, resizing the window at each; after each full tour
        /// print the resident memory and the live Vulkan objects (the soak test).
        #[arg(long, value_name = "N")]
        tour: Option<u32>,
        /// How frames reach the window: drawn into the swapchain image, a multisampled frame
        /// resolved into it in the render pass (`direct`, where its format allows), or drawn
        /// offscreen and copied in (`copy`, to compare what the copy costs).
        #[arg(long, value_enum, default_value_t = PresentPath::Direct, value_name = "PATH")]
        present: PresentPath,
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
    /// Technique to render (`bench` also takes `all`, or a list such as `shadow-volume,shadow-map` to
    /// compare whole techniques in one run).
    #[arg(long, default_value = DEFAULT_TECHNIQUE)]
    pub technique: String,
    /// Where skinned objects are posed: `gpu`, in every technique's vertex stage, or `cpu`,
    /// re-skinned on the CPU when the pose changes (the oracle).
    #[arg(long, value_enum, default_value_t)]
    pub skinning: Skinning,
    /// Built-in scene name (see `nostencil info`) or a .gltf/.glb file.
    #[arg(long, default_value = "default")]
    pub scene: String,
    /// Animation time in seconds: a glTF scene's first animation (looping), the built-in character's walk.
    #[arg(long, default_value_t = 0.0, value_name = "SECONDS")]
    pub time: f32,
    /// Adds a light to the scene's (repeatable): KIND[:key=value]..., KIND directional, point or
    /// spot; keys name, at=x,y,z, dir=x,y,z, aim=x,y,z, colour=r,g,b, intensity, range, inner and
    /// outer (degrees), shadows=on|off. Example: point:at=2,4,1:colour=1,0.3,0.2:intensity=20:range=8
    #[arg(long = "light", value_name = "SPEC", value_parser = parse_light_arg)]
    pub lights: Vec<SceneLight>,
    /// The --light lights replace the scene's (or the file's) lights instead of adding to them.
    #[arg(long, requires = "lights")]
    pub replace_lights: bool,
    // glTF intensities are physical (candela, lux): a file exported in watts lights far brighter
    // than the built-in scenes' units, and saturates.
    /// Multiplies every light's intensity (ambient and emissive stay): e.g. 0.01 for a file whose
    /// lights saturate the frame.
    #[arg(long, default_value_t = 1.0, value_name = "F", value_parser = parse_light_scale)]
    pub light_scale: f32,
    // Each technique family's options and their flags, declared by the family (`technique`):
    // moved as they are into `RenderOptions`.
    #[command(flatten)]
    pub shadow_volume: ShadowVolumeOptions,
    #[command(flatten)]
    pub cartoon: CartoonOptions,
    #[command(flatten)]
    pub shadow_tone: SharedShadowArgs,
    #[command(flatten)]
    pub planar: PlanarOptions,
    #[command(flatten)]
    pub shadow_atlas: ShadowAtlasOptions,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

fn parse_light_scale(value: &str) -> std::result::Result<f32, String> {
    match value.trim().parse::<f32>() {
        Ok(scale) if scale.is_finite() && scale >= 0.0 => Ok(scale),
        _ => Err(format!("'{value}' is not a number >= 0")),
    }
}

fn parse_light_arg(spec: &str) -> std::result::Result<SceneLight, String> {
    crate::scene::lights::parse_light_spec(spec).map_err(|e| e.to_string())
}

/// `view`'s scripted events (for tests), typed where they are parsed: `--resize-after N WxH` and
/// `--press-after N KEY` (two values each, which clap's derive cannot type one by one).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ViewScript {
    /// After this many presented frames, resize the window to this size.
    pub resize_after: Option<(u32, (u32, u32))>,
    /// After this many presented frames, act as if this key was pressed.
    pub press_after: Option<(u32, char)>,
}

impl Args for ViewScript {
    fn augment_args(command: clap::Command) -> clap::Command {
        command
            .arg(
                clap::Arg::new("resize_after")
                    .long("resize-after")
                    .num_args(2)
                    .value_names(["N", "WxH"])
                    .help("After N presented frames, resize the window to WxH (for tests of the resize path)"),
            )
            .arg(clap::Arg::new("press_after").long("press-after").num_args(2).value_names(["N", "KEY"]).help(
                "After N presented frames, act as if KEY (a letter from the key list) was pressed (for tests of a \
                 live switch, such as M for the sample count)",
            ))
    }

    fn augment_args_for_update(command: clap::Command) -> clap::Command {
        ViewScript::augment_args(command)
    }
}

impl FromArgMatches for ViewScript {
    fn from_arg_matches(matches: &ArgMatches) -> std::result::Result<Self, clap::Error> {
        let invalid = |e: Error| clap::Error::raw(clap::error::ErrorKind::ValueValidation, format!("{e}\n"));
        let pair = |id: &str| -> Option<[String; 2]> {
            let values: Vec<String> = matches.get_many::<String>(id)?.cloned().collect();
            <[String; 2]>::try_from(values).ok()
        };
        let resize_after = match pair("resize_after") {
            Some([after, size]) => {
                Some((frame_count("--resize-after", &after).map_err(invalid)?, parse_size(&size).map_err(invalid)?))
            }
            None => None,
        };
        let press_after = match pair("press_after") {
            Some([after, key]) => Some((
                frame_count("--press-after", &after).map_err(invalid)?,
                crate::viewer::keys::scripted_key(&key).map_err(invalid)?,
            )),
            None => None,
        };
        Ok(ViewScript { resize_after, press_after })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> std::result::Result<(), clap::Error> {
        *self = ViewScript::from_arg_matches(matches)?;
        Ok(())
    }
}

/// `--resize-after`'s or `--press-after`'s frame count.
fn frame_count(flag: &str, text: &str) -> Result<u32> {
    text.parse().map_err(|_| Error::InvalidInput(format!("{flag} {text}: expected a frame count, such as 3")))
}

/// `nostencil layer ...`.
#[derive(Debug, Subcommand)]
pub enum LayerAction {
    /// Copy libnostencil_fillrate.so to ~/.local/lib/nostencil/ and write its manifest to
    /// $XDG_DATA_HOME/vulkan/explicit_layer.d/ (default ~/.local/share/...).
    Install {
        /// The layer library to install; default: the one built beside this executable.
        #[arg(long, value_name = "PATH")]
        library: Option<PathBuf>,
    },
    /// Remove what `layer install` wrote.
    Uninstall,
}

/// The page and the JUnit verdict of a `profile` or `profile-app` run.
#[derive(Debug, Clone, Args)]
pub struct PageArgs {
    /// Also write one self-contained HTML page of the run: the budget's verdict, charts, the
    /// per-pass table with budget margins, the findings and images the run has (the tiler
    /// check's with advice, the captured frame, the heat map), and the JSON report embedded
    /// (docs/profiling.md, "One page per run").
    #[arg(long, value_name = "FILE.html")]
    pub html: Option<PathBuf>,
    /// With --budget: also write the verdict as JUnit XML, a test case per budgeted pass,
    /// failed with its margin where over (for CI's test reporters).
    #[arg(long, value_name = "FILE.xml", requires = "budget")]
    pub junit: Option<PathBuf>,
}

/// `profile-app --frame-on` (the layer's NOSTENCIL_FILLRATE_FRAME_ON).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FrameOnArg {
    Present,
    Submit,
    Wait,
    Swap,
}

impl FrameOnArg {
    pub fn name(self) -> &'static str {
        match self {
            FrameOnArg::Present => "present",
            FrameOnArg::Submit => "submit",
            FrameOnArg::Wait => "wait",
            FrameOnArg::Swap => "swap",
        }
    }
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

fn parse_size_arg(text: &str) -> std::result::Result<(u32, u32), String> {
    parse_size(text).map_err(|e| e.to_string())
}

/// `passes`' options: the frames' shadow-volume flags and shadow tone, the same flattened
/// structs, except that `--normalize` and `--volume-method` keep only that path's plans (every
/// plan by default) instead of choosing one path.
#[derive(Debug, Clone)]
pub struct PassesArgs {
    pub shadow_volume: ShadowVolumeOptions,
    pub shadow_tone: SharedShadowArgs,
    /// `--normalize`, if given.
    pub only_normalize: Option<Normalize>,
    /// `--volume-method`, if given and not `auto`.
    pub only_method: Option<VolumeMethod>,
}

impl FromArgMatches for PassesArgs {
    fn from_arg_matches(matches: &ArgMatches) -> std::result::Result<Self, clap::Error> {
        let given = |id: &str| matches.value_source(id) == Some(ValueSource::CommandLine);
        let shadow_volume = ShadowVolumeOptions::from_arg_matches(matches)?;
        Ok(PassesArgs {
            only_normalize: given("normalize").then_some(shadow_volume.normalize),
            only_method: (shadow_volume.method != VolumeMethod::Auto).then_some(shadow_volume.method),
            shadow_volume,
            shadow_tone: SharedShadowArgs::from_arg_matches(matches)?,
        })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> std::result::Result<(), clap::Error> {
        *self = PassesArgs::from_arg_matches(matches)?;
        Ok(())
    }
}

impl Args for PassesArgs {
    fn augment_args(command: clap::Command) -> clap::Command {
        SharedShadowArgs::augment_args(ShadowVolumeOptions::augment_args(command))
            .mut_arg("normalize", |arg| {
                arg.help("shadow-volume: list only this normalisation path; all by default").hide_default_value(true)
            })
            .mut_arg("volume_method", |arg| {
                arg.help("shadow-volume: list only this counting method's plans; `auto`: both")
            })
    }

    fn augment_args_for_update(command: clap::Command) -> clap::Command {
        PassesArgs::augment_args(command)
    }
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
