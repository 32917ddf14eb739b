//! What each subcommand does.

use std::path::Path;

use super::args::{
    Cli, Command, FormatArg, FrameArgs, FrameOnArg, GpuArgs, LayerAction, PageArgs, PassesArgs, ViewScript,
};
use super::frame_setup::{load_named_scene, load_scene, open_gpu, open_gpu_with, options, print_warnings};
use super::output_path::check_output_path;
use super::profile_frame::ProfileOutputs;
use crate::error::{Error, Result};
use crate::frame::render_pass::COLOUR_FORMAT;
use crate::frame::targets::{choose_depth_format, offered_samples};
use crate::frame::StencilMode;
use crate::gpu::validation::ValidationReport;
use crate::gpu::{mobile_profile, DeviceChoice, GpuOptions};
use crate::profile::report::ReportFormat;
use crate::scene::{Scene, BUILTIN_SCENES, OTHER_SCENES};
use crate::technique::registry::shadowing_every_light;
use crate::technique::{by_name, render_scene, shadow_atlas, RenderOptions, TECHNIQUES};
use crate::viewer::PresentPath;

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render { frame, out, keep_alpha, no_queries } => render(&frame, &out, keep_alpha, no_queries),
        Command::Profile {
            frame,
            format,
            compare,
            heatmap,
            chart,
            budget,
            record_budget,
            page: PageArgs { html, junit },
            trace,
            move_model,
            caster_fill,
        } => {
            let outputs =
                ProfileOutputs { heatmap, chart, budget, record_budget, html, junit, trace, move_model, caster_fill };
            if compare.is_empty() {
                super::profile_frame::profile(&frame, report_format(format), &outputs)
            } else if outputs.trace.is_some() || outputs.html.is_some() {
                Err(Error::InvalidInput("--trace and --html write one frame's report: drop --compare".into()))
            } else {
                profile_compare(&frame, format, &compare)
            }
        }
        Command::Info { gpu, json } => info(&gpu, json),
        Command::ProfileApp {
            frames,
            keep_running,
            seconds,
            per_draw,
            tiler_check,
            frame_on,
            gl,
            device,
            format,
            budget,
            record_budget,
            page: PageArgs { html, junit },
            chart,
            trace,
            out,
            capture,
            capture_frame,
            command,
        } => {
            let frame_on = match (frame_on, gl) {
                (Some(FrameOnArg::Swap), false) => {
                    return Err(Error::InvalidInput(
                        "--frame-on swap cuts frames at a GL program's buffer swaps: give --gl too".into(),
                    ))
                }
                (Some(on), _) => on,
                (None, true) => FrameOnArg::Swap,
                (None, false) => FrameOnArg::Present,
            };
            let capture = capture.map(|path| (path, capture_frame));
            let outputs = super::profile_app::AppOutputs {
                budget,
                record_budget,
                chart,
                trace,
                out,
                per_draw,
                tiler_check,
                frame_on: frame_on.name(),
                gl: gl.then(|| device.as_deref().map(DeviceChoice::parse).unwrap_or_default().from_env_or()),
                capture,
                html,
                junit,
            };
            let stop = super::supervise::Stop { frames, seconds, keep_running };
            super::profile_app::run(&command, stop, report_format(format), &outputs)
        }
        Command::Layer { action } => {
            let paths = super::install::InstallPaths::current()?;
            match action {
                LayerAction::Install { library } => super::install::install(library.as_deref(), &paths),
                LayerAction::Uninstall => super::install::uninstall(&paths),
            }
        }
        Command::Passes { technique, scene, lights, replace_lights, samples, plans } => {
            let scene = load_named_scene(&scene, 0.0, &lights, replace_lights)?;
            passes(&technique, &plans, &scene, samples)
        }
        Command::Bench { format: Some(FormatArg::Csv), .. } => {
            Err(Error::InvalidInput("bench writes a table or JSON: --format table or --format json".into()))
        }
        Command::Bench { html: Some(_), mip_flicker: Some(_), .. }
        | Command::Bench { html: Some(_), frame_loop: Some(_), .. } => {
            Err(Error::InvalidInput("--html writes timed variants' page: drop --mip-flicker and --loop".into()))
        }
        Command::Bench {
            frame,
            warmup: _,
            runs,
            json,
            format,
            trace,
            table1_out,
            mip_flicker: Some(steps),
            frame_loop,
            each_extrusion,
            ..
        } => {
            if table1_out.is_some() || runs.is_some() || trace.is_some() || frame_loop.is_some() || each_extrusion {
                return Err(Error::InvalidInput(
                    "--mip-flicker is not timed: drop --table1-out, --runs, --trace, --loop and --each-extrusion"
                        .into(),
                ));
            }
            bench_mip_flicker(&frame, steps, json || format == Some(FormatArg::Json))
        }
        Command::Bench {
            frame,
            warmup,
            runs,
            json,
            trace,
            table1_out,
            mip_flicker: None,
            frame_loop: Some(frames),
            frames_in_flight,
            each_extrusion,
            each_skinning,
            format,
            html: _,
        } => {
            let json = json || format == Some(FormatArg::Json);
            if table1_out.is_some() || runs.is_some() || trace.is_some() {
                return Err(Error::InvalidInput(
                    "--loop plays N frames of each technique: drop --table1-out, --runs and --trace".into(),
                ));
            }
            let playing = super::frame_loop::Playing {
                frames,
                in_flight: frames_in_flight,
                warmup,
                each_extrusion,
                each_skinning,
            };
            super::frame_loop::bench_loop(&frame, playing, json)
        }
        Command::Bench { each_extrusion: true, frame_loop: None, .. } => Err(Error::InvalidInput(
            "--each-extrusion plays shadow-volume once per volume extrusion in a frame loop: add --loop N".into(),
        )),
        Command::Bench {
            frame,
            warmup,
            runs,
            json,
            format,
            html,
            trace,
            table1_out,
            mip_flicker: None,
            frame_loop: None,
            ..
        } => {
            if (trace.is_some() || html.is_some()) && (frame.technique == "all" || table1_out.is_some()) {
                return Err(Error::InvalidInput(
                    "--trace and --html write one technique's frames: give one --technique, without --table1-out"
                        .into(),
                ));
            }
            let json = json || format == Some(FormatArg::Json);
            let outputs = super::bench::BenchOutputs { trace: trace.as_deref(), html: html.as_deref() };
            super::bench::bench(&frame, warmup, runs, json, table1_out.as_deref(), outputs)
        }
        Command::Bake { frame, model, mip, out } => bake(&frame, model.as_deref(), mip, &out),
        Command::View { frame, frames, screenshot, script, paused, tour, present } => {
            view(&frame, frames, screenshot, script, (tour, paused), present)
        }
    }
}

fn render(frame: &FrameArgs, out: &Path, keep_alpha: bool, no_queries: bool) -> Result<()> {
    check_output_path(out)?;
    let options = options(frame)?;
    let scene = load_scene(frame)?;
    let gpu = open_gpu_with(&frame.gpu, no_queries)?;
    let frame = render_scene(&gpu, &scene, &options)?;
    print_warnings(options.technique.name(), &frame.warnings);
    let output = &frame.output;
    crate::frame::write_png(&output.image, out, keep_alpha)?;
    let gpu_time = if no_queries {
        "GPU time not measured".to_owned()
    } else {
        format!("{:.2} ms GPU", output.counters.total_gpu_ms())
    };
    eprintln!(
        "wrote {} ({}x{}, {} on {}, {gpu_time})",
        out.display(),
        options.width,
        options.height,
        options.technique.name(),
        gpu.device.info.name,
    );
    Ok(())
}

fn report_format(format: FormatArg) -> ReportFormat {
    match format {
        FormatArg::Table => ReportFormat::Table,
        FormatArg::Json => ReportFormat::Json,
        FormatArg::Csv => ReportFormat::Csv,
    }
}

/// Bakes the shadow textures of `frame.scene` and writes one model's as PNG.
fn bake(frame: &FrameArgs, model: Option<&str>, mip: u32, out: &Path) -> Result<()> {
    use crate::technique::shadow_atlas::BakeStep;
    check_output_path(out)?;
    let options = options(frame)?;
    let scene = load_scene(frame)?;
    let object = match model {
        Some(name) => scene.objects.iter().position(|o| o.name == name).ok_or_else(|| {
            Error::InvalidInput(format!(
                "no model '{name}' in scene '{}'; models: {}",
                scene.name,
                scene.objects.iter().map(|o| o.name.as_str()).collect::<Vec<_>>().join(", ")
            ))
        })?,
        // The first model that casts shadows (the ground would be a dull default).
        None => scene.objects.iter().position(|o| o.casts_shadow).unwrap_or(0),
    };
    let gpu = open_gpu(&frame.gpu)?;
    let start = std::time::Instant::now();
    let bake_options =
        RenderOptions { width: options.width.min(64), height: options.height.min(64), ..options.clone() };
    // One progress line on a terminal: the atlas layout mesh by mesh, then the bake itself.
    let progress = indicatif::ProgressBar::new(0);
    if let Ok(style) = indicatif::ProgressStyle::with_template("bake: {msg} {pos:>4}/{len}") {
        progress.set_style(style);
    }
    progress.set_message("atlas layout");
    let baked = shadow_atlas::bake(&gpu, &scene, &bake_options, &mut |step| match step {
        BakeStep::Layout { done, total } => {
            progress.set_length(total as u64);
            progress.set_position(done as u64);
        }
        BakeStep::Rendering => {
            if let Ok(style) = indicatif::ProgressStyle::with_template("bake: {msg}") {
                progress.set_style(style);
            }
            progress.set_message(format!("shadow map and {} shadow textures...", scene.objects.len()));
        }
    });
    // An error replaces the progress line rather than continuing it.
    progress.finish_and_clear();
    let renderer = baked?;
    eprintln!(
        "bake: shadow map and {} shadow textures baked in {:.0} ms",
        scene.objects.len(),
        start.elapsed().as_secs_f64() * 1e3
    );
    let image = renderer.read_shadow_texture(object, mip)?;
    crate::frame::write_png(&image, out, false)?;
    let name = &scene.objects.get(object).map_or("", |o| o.name.as_str());
    let atlas = scene.objects.get(object).and_then(|o| renderer.atlases().get(o.mesh));
    eprintln!(
        "wrote {} ({}x{}, mip {mip} of '{name}' in scene '{}'; atlas: {})",
        out.display(),
        image.width(),
        image.height(),
        scene.name,
        atlas.map_or("?".into(), |a| a.describe())
    );
    Ok(())
}

/// `--compare`: each named variant of the frame, side by side.
fn profile_compare(frame: &FrameArgs, format: FormatArg, variants: &[String]) -> Result<()> {
    use crate::profile::compare::{Comparison, VariantFrame};
    let base = options(frame)?;
    let scene = load_scene(frame)?;
    let gpu = open_gpu(&frame.gpu)?;
    let mut frames = Vec::new();
    for variant in variants {
        let options = base.technique.compare_variant(variant, &base)?;
        render_scene(&gpu, &scene, &options)?; // warm-up: shader compilation
        let counters = render_scene(&gpu, &scene, &options)?.output.counters;
        frames.push(VariantFrame { variant: variant.clone(), counters });
    }
    let comparison = Comparison::new(frames);
    match format {
        FormatArg::Table => print!("{}", comparison.table()),
        FormatArg::Json => {
            println!("{}", serde_json::to_string_pretty(&comparison).map_err(|e| Error::Internal(e.to_string()))?)
        }
        FormatArg::Csv => print!("{}", comparison.csv()),
    }
    Ok(())
}

#[derive(serde::Serialize)]
struct InfoReport<'a> {
    device: &'a str,
    device_index: usize,
    device_type: String,
    api_version: String,
    profile: &'static str,
    enabled_features: mobile_profile::EnabledFeatures,
    forbidden_features: &'static [&'static str],
    lazily_allocated_memory: bool,
    /// The frame's formats: colour (sRGB, alpha linear) and depth per stencil mode.
    frame_colour_format: String,
    frame_depth_format_emulated: String,
    frame_depth_format_reference: String,
    /// The samples per pixel `--samples` may ask for, per stencil mode.
    frame_samples_emulated: Vec<u32>,
    frame_samples_reference: Vec<u32>,
    limits: &'a [mobile_profile::LimitCheck],
    /// The validation layer's active checks (`--validation`); null when validation is off.
    validation: Option<&'a ValidationReport>,
    scenes: Vec<&'static str>,
    techniques: Vec<&'static str>,
    /// The techniques that shadow every light in the additive mode.
    shadowing_every_light: Vec<&'static str>,
}

fn info(args: &GpuArgs, json: bool) -> Result<()> {
    let gpu = open_gpu(args)?;
    let info = &gpu.device.info;
    let version = |v: u32| {
        format!("{}.{}.{}", ash::vk::api_version_major(v), ash::vk::api_version_minor(v), ash::vk::api_version_patch(v))
    };
    let report = InfoReport {
        device: &info.name,
        device_index: info.index,
        device_type: format!("{:?}", info.device_type),
        api_version: version(info.api_version),
        profile: "mobile (after VP_ANDROID_baseline_2022)",
        enabled_features: info.features,
        forbidden_features: &mobile_profile::FORBIDDEN_FEATURES,
        lazily_allocated_memory: info.has_lazily_allocated_memory,
        frame_colour_format: format!("{COLOUR_FORMAT:?}"),
        frame_depth_format_emulated: format!("{:?}", choose_depth_format(&gpu, StencilMode::Emulated)?),
        frame_depth_format_reference: format!("{:?}", choose_depth_format(&gpu, StencilMode::Reference)?),
        frame_samples_emulated: offered_samples(&gpu, StencilMode::Emulated),
        frame_samples_reference: offered_samples(&gpu, StencilMode::Reference),
        limits: &info.limit_checks,
        validation: gpu.validation_report(),
        scenes: BUILTIN_SCENES.iter().chain(OTHER_SCENES).map(|(n, _)| *n).collect(),
        techniques: TECHNIQUES.iter().map(|t| t.name()).collect(),
        shadowing_every_light: shadowing_every_light(),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&report).map_err(|e| Error::Internal(e.to_string()))?);
        return Ok(());
    }
    println!(
        "device:    {} (index {}, {}, Vulkan {})",
        report.device, report.device_index, report.device_type, report.api_version
    );
    println!("profile:   {}", report.profile);
    println!(
        "enabled:   occlusionQueryPrecise={} fragmentStoresAndAtomics={} pipelineStatisticsQuery={} (profiling only; not in the baseline)",
        info.features.occlusion_query_precise,
        info.features.fragment_stores_and_atomics,
        info.features.pipeline_statistics_query
    );
    println!("forbidden: {} (all disabled)", mobile_profile::FORBIDDEN_FEATURES.join(", "));
    println!(
        "transient attachments: {}",
        if info.has_lazily_allocated_memory {
            "lazily allocated memory"
        } else {
            "no LAZILY_ALLOCATED memory type: ordinary device memory"
        }
    );
    println!(
        "frame:     colour {} (sRGB-encoded RGB; alpha linear, the counter), depth {} (emulated) / {} (reference)",
        report.frame_colour_format, report.frame_depth_format_emulated, report.frame_depth_format_reference
    );
    let listed = |counts: &[u32]| counts.iter().map(u32::to_string).collect::<Vec<_>>().join(", ");
    println!(
        "samples:   {} (emulated) / {} (reference) per pixel for --samples",
        listed(&report.frame_samples_emulated),
        listed(&report.frame_samples_reference)
    );
    println!("\n{:<36} {:>10} {:>12}  ok", "limit", "profile", "device");
    for check in report.limits {
        println!(
            "{:<36} {:>10} {:>12}  {}",
            check.name,
            check.profile,
            check.device,
            if check.ok { "yes" } else { "NO" }
        );
    }
    print_validation(report.validation);
    println!("\nscenes:     {}", report.scenes.join(", "));
    println!("techniques: {}", report.techniques.join(", "));
    println!("shadowing every light (--shadow-mode additive): {}", report.shadowing_every_light.join(", "));
    Ok(())
}

/// The validation part of `info`: which checks are on and which messages are silenced, and why.
fn print_validation(report: Option<&ValidationReport>) {
    let Some(v) = report else {
        println!("\nvalidation: off (--validation turns on the Khronos layer and its checks)");
        return;
    };
    let on = |b: bool| if b { "on" } else { "off" };
    println!("\nvalidation: {}", v.layer);
    println!(
        "  checks:   core {}, synchronization {}, best practices {}, GPU-assisted {}, debug printf {}",
        on(v.core),
        on(v.synchronization),
        on(v.best_practices),
        on(v.gpu_assisted),
        on(v.debug_printf)
    );
    println!("  recorded: {}", v.recorded);
    for silenced in v.silenced {
        println!("  silenced: {}: {}", silenced.id, silenced.why);
    }
}

/// `bench --mip-flicker`: seed 004's anti-aliasing claim measured on `--scene`.
fn bench_mip_flicker(frame: &FrameArgs, steps: u32, json: bool) -> Result<()> {
    let options = options(frame)?;
    if !crate::profile::mip_flicker::compares(options.technique) {
        return Err(Error::InvalidInput(format!(
            "--mip-flicker compares seed 004's shadow texture and shadow map: use it with --technique shadow-texture-atlas or shadow-map, not {}",
            options.technique.name()
        )));
    }
    let scene = load_scene(frame)?;
    let gpu = open_gpu(&frame.gpu)?;
    let report = crate::profile::mip_flicker::measure(&gpu, &scene, &options, steps)?;
    if json {
        println!("{}", serde_json::to_string_pretty(&report).map_err(|e| Error::Internal(e.to_string()))?);
    } else {
        print!("{}", report.render());
    }
    Ok(())
}

fn view(
    frame: &FrameArgs,
    frames: Option<u32>,
    screenshot: Option<std::path::PathBuf>,
    script: ViewScript,
    (tour, paused): (Option<u32>, bool),
    present: PresentPath,
) -> Result<()> {
    use crate::viewer::{live::Settings, ViewerOptions};

    if let Some(path) = &screenshot {
        if frames.is_none() {
            return Err(Error::InvalidInput(
                "--screenshot needs --frames N: the screenshot is of the last frame".into(),
            ));
        }
        check_output_path(path)?;
    }
    if frames == Some(0) {
        return Err(Error::InvalidInput("--frames must be at least 1".into()));
    }
    if tour == Some(0) {
        return Err(Error::InvalidInput("--tour must be at least 1 (frames per stop)".into()));
    }
    let options = options(frame)?;
    let scene = load_scene(frame)?;
    let device = frame.gpu.device.as_deref().map(DeviceChoice::parse).unwrap_or_default();
    crate::viewer::run(
        ViewerOptions {
            settings: Settings { render: options },
            size: frame.size,
            gpu: GpuOptions { validation: frame.gpu.validation, device, without_pass_queries: false },
            frames,
            screenshot,
            resize_after: script.resize_after,
            press_after: script.press_after,
            tour,
            paused,
            start_time: frame.time,
            present,
        },
        scene,
    )
}

/// `passes`: every plan of the technique (each path, each variant that changes the passes), as
/// Markdown tables; `--normalize` keeps one shadow-volume normalisation. For shadow volumes,
/// the plans are for k, D (or the tint) of `shadow_volume`, and the table of iteration counts
/// for other k and D follows them.
fn passes(technique: &str, plans: &PassesArgs, scene: &Scene, samples: u32) -> Result<()> {
    let technique = by_name(technique)?;
    let base = RenderOptions {
        technique,
        shadow_volume: plans.shadow_volume,
        shadow_mode: plans.shadow_tone.shadow_mode,
        shadow_tone: plans.shadow_tone.tone(),
        samples,
        ..Default::default()
    };
    base.check()?;
    // The lights its renderer would loop over for this scene.
    let lights = technique.planned_lights(scene);
    println!("## {}: passes and fixed-function state\n", technique.name());
    println!("{}\n", technique.about());
    let variants = technique.plan_variants(&base);
    let normalisations =
        variants.iter().map(|v| v.options.shadow_volume.normalize).collect::<std::collections::HashSet<_>>().len();
    let methods =
        variants.iter().map(|v| v.options.shadow_volume.method).collect::<std::collections::HashSet<_>>().len();
    for variant in variants {
        // `--normalize` keeps the reference and that normalisation's plans, `--volume-method`
        // that method's, for techniques whose plans depend on them.
        let volumes = &variant.options.shadow_volume;
        let kept_normalize = match plans.only_normalize {
            Some(n) if normalisations > 1 => {
                variant.options.stencil == StencilMode::Reference || volumes.normalize == n
            }
            _ => true,
        };
        let kept = kept_normalize
            && match plans.only_method {
                Some(m) if methods > 1 => volumes.method == m,
                _ => true,
            };
        if kept {
            let plan = technique.plan(&variant.options, &lights)?;
            println!("{}", crate::profile::passes::plan_table(&variant.label, &plan));
        }
    }
    if let Some(notes) = technique.plan_notes()? {
        println!("{notes}");
    }
    Ok(())
}
