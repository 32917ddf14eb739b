//! What each subcommand does.

use std::path::Path;
use std::sync::Arc;

use super::args::{Cli, Command, FormatArg, FrameArgs, GpuArgs};
use crate::error::{Error, Result};
use crate::gpu::{mobile_profile, DeviceChoice, Gpu, GpuOptions};
use crate::profile::budget::Budget;
use crate::profile::report::{ProfileReport, ReportContext, ReportFormat};
use crate::scene::{builtin_scene, scene_from_gltf, Scene, BUILTIN_SCENES};
use crate::technique::{
    alpha_counter, render_scene, Normalize, RenderOptions, ShadowVolumeOptions, Technique, VolumeMethod,
};

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Render { frame, out, keep_alpha } => render(&frame, &out, keep_alpha),
        Command::Profile { frame, format, compare, heatmap, chart, budget, write_budget } => {
            let outputs = ProfileOutputs { heatmap, chart, budget, write_budget };
            if compare.is_empty() {
                profile(&frame, format, &outputs)
            } else {
                profile_compare(&frame, format, &compare)
            }
        }
        Command::Info { gpu, json } => info(&gpu, json),
        Command::Passes { technique, normalize } => {
            let options = RenderOptions {
                technique: Technique::parse(&technique)?,
                shadow_volume: ShadowVolumeOptions { normalize: Normalize::parse(&normalize)?, ..Default::default() },
                ..Default::default()
            };
            let descs = crate::technique::pipeline_descs(&options);
            print!("{}", crate::profile::passes::markdown_table(options.technique.name(), &descs));
            Ok(())
        }
        Command::Bench { frame, warmup, runs, json } => bench(&frame, warmup, runs, json),
        Command::View { frame, frames, screenshot, resize_after, paused } => {
            view(&frame, frames, screenshot, resize_after, paused)
        }
    }
}

fn open_gpu(args: &GpuArgs) -> Result<Arc<Gpu>> {
    let device = args.device.as_deref().map(DeviceChoice::parse).unwrap_or_default();
    Gpu::new(&GpuOptions { validation: args.validation, device })
}

/// A built-in scene by name, or a .gltf/.glb file posed at `time` seconds.
fn load_scene(name: &str, time: f32) -> Result<Scene> {
    let path = Path::new(name);
    let is_gltf = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"));
    if is_gltf || path.exists() {
        scene_from_gltf(path, time)
    } else {
        builtin_scene(name)
    }
}

fn options(frame: &FrameArgs) -> Result<RenderOptions> {
    Ok(RenderOptions {
        width: frame.size.0,
        height: frame.size.1,
        stencil: frame.stencil.into(),
        technique: Technique::parse(&frame.technique)?,
        shadow_volume: ShadowVolumeOptions {
            increment: alpha_counter::check_increment(frame.increment)?,
            method: VolumeMethod::parse(&frame.volume_method)?,
            normalize: Normalize::parse(&frame.normalize)?,
            ..Default::default()
        },
        count_overdraw: false,
    })
}

/// Refuses an output path whose folder does not exist before any rendering is done.
fn check_output_path(path: &Path) -> Result<()> {
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(Error::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "the output folder does not exist"),
        });
    }
    if path.is_dir() {
        return Err(Error::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::InvalidInput, "the output path is a folder"),
        });
    }
    Ok(())
}

fn render(frame: &FrameArgs, out: &Path, keep_alpha: bool) -> Result<()> {
    check_output_path(out)?;
    let options = options(frame)?;
    let scene = load_scene(&frame.scene, frame.time)?;
    let gpu = open_gpu(&frame.gpu)?;
    let frame = render_scene(&gpu, &scene, &options)?;
    let output = &frame.output;
    output.image.write_png(out, keep_alpha)?;
    eprintln!(
        "wrote {} ({}x{}, {} on {}, {:.2} ms GPU)",
        out.display(),
        options.width,
        options.height,
        options.technique.name(),
        gpu.device.info.name,
        output.counters.total_gpu_ms()
    );
    Ok(())
}

struct ProfileOutputs {
    heatmap: Option<std::path::PathBuf>,
    chart: Option<std::path::PathBuf>,
    budget: Option<std::path::PathBuf>,
    write_budget: Option<std::path::PathBuf>,
}

fn report_format(format: FormatArg) -> ReportFormat {
    match format {
        FormatArg::Table => ReportFormat::Table,
        FormatArg::Json => ReportFormat::Json,
        FormatArg::Csv => ReportFormat::Csv,
    }
}

fn profile(frame: &FrameArgs, format: FormatArg, outputs: &ProfileOutputs) -> Result<()> {
    for path in [&outputs.heatmap, &outputs.chart, &outputs.write_budget].into_iter().flatten() {
        check_output_path(path)?;
    }
    let options = options(frame)?;
    let scene = load_scene(&frame.scene, frame.time)?;
    let gpu = open_gpu(&frame.gpu)?;
    // One frame first: llvmpipe compiles shaders at first draw, which is not the frame's cost.
    render_scene(&gpu, &scene, &options)?;
    let frame_result = render_scene(&gpu, &scene, &options)?;
    let output = &frame_result.output;
    let depth_format = crate::frame::targets::choose_depth_format(&gpu, options.stencil)?;
    let attachments =
        crate::frame::RenderPassDesc::frame(depth_format, false).tile_traffic(options.width, options.height);
    let (technique, stencil) = (options.technique.name(), options.stencil.name());
    let mut report = ProfileReport::new(
        ReportContext {
            device: gpu.device.info.name.clone(),
            scene: scene.name.clone(),
            technique: technique.into(),
            stencil: stencil.into(),
        },
        &output.counters,
        attachments,
    );
    report.technique_stats = frame_result.shadow_volume.and_then(|s| serde_json::to_value(s).ok());
    print!("{}", report.render(report_format(format)));
    if let (Some(stats), FormatArg::Table) = (frame_result.shadow_volume, format) {
        println!(
            "\nshadow volumes: {} | counter capacity {} volumes (k = {}) | saturated pixels: {}",
            if stats.zfail { "z-fail" } else { "z-pass" },
            stats.capacity,
            options.shadow_volume.increment,
            stats.saturated_pixels.map_or("n/a (reference)".to_owned(), |n| n.to_string())
        );
    }

    if let Some(path) = &outputs.heatmap {
        let counting = RenderOptions { count_overdraw: true, ..options.clone() };
        let counted = render_scene(&gpu, &scene, &counting)?;
        crate::profile::heatmap::render_heatmap(&counted.output.image).write_png(path, false)?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &outputs.chart {
        let title = format!("{technique} ({stencil}) on {}, {}x{}", scene.name, options.width, options.height);
        let svg = crate::profile::chart::bar_chart_svg(&title, &output.counters);
        crate::frame::image::write_atomically(path, svg.as_bytes())?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &outputs.write_budget {
        Budget::from_frame(&scene.name, technique, stencil, &output.counters).write(path)?;
        eprintln!("wrote budget {}", path.display());
    }
    if let Some(path) = &outputs.budget {
        let overruns = Budget::load(path)?.check(&scene.name, technique, stencil, &output.counters)?;
        if !overruns.is_empty() {
            for overrun in &overruns {
                eprintln!("over budget: {overrun}");
            }
            let passes: std::collections::BTreeSet<&str> = overruns.iter().map(|o| o.pass.as_str()).collect();
            return Err(Error::InvalidInput(format!(
                "{} pass(es) over the budget in {}: {}",
                passes.len(),
                path.display(),
                passes.into_iter().collect::<Vec<_>>().join(", ")
            )));
        }
        eprintln!("within budget {}", path.display());
    }
    Ok(())
}

/// `--compare`: each named variant of the frame, side by side.
fn profile_compare(frame: &FrameArgs, format: FormatArg, variants: &[String]) -> Result<()> {
    use crate::frame::StencilMode;
    use crate::profile::compare::{Comparison, VariantFrame};
    let base = options(frame)?;
    let scene = load_scene(&frame.scene, frame.time)?;
    let gpu = open_gpu(&frame.gpu)?;
    let mut frames = Vec::new();
    for variant in variants {
        let mut options = base.clone();
        match variant.as_str() {
            "emulated" => options.stencil = StencilMode::Emulated,
            "reference" => options.stencil = StencilMode::Reference,
            other => {
                if options.technique != Technique::ShadowVolume {
                    return Err(Error::InvalidInput(format!(
                        "--compare {other}: variants are emulated and reference (and seed, max, subpass for shadow-volume)"
                    )));
                }
                options.stencil = StencilMode::Emulated;
                options.shadow_volume.normalize = Normalize::parse(other)?;
            }
        }
        render_scene(&gpu, &scene, &options)?; // warm-up: shader compilation
        let counters = render_scene(&gpu, &scene, &options)?.output.counters;
        frames.push(VariantFrame { variant: variant.clone(), counters });
    }
    let comparison = Comparison::new(frames);
    match format {
        FormatArg::Table => print!("{}", comparison.table()),
        FormatArg::Json => {
            println!("{}", serde_json::to_string_pretty(&comparison).map_err(|e| Error::InvalidInput(e.to_string()))?)
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
    limits: &'a [mobile_profile::LimitCheck],
    scenes: Vec<&'static str>,
    techniques: Vec<&'static str>,
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
        limits: &info.limit_checks,
        scenes: BUILTIN_SCENES.iter().map(|(n, _)| *n).collect(),
        techniques: Technique::ALL.iter().map(|t| t.name()).collect(),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&report).map_err(|e| Error::InvalidInput(e.to_string()))?);
        return Ok(());
    }
    println!(
        "device:    {} (index {}, {}, Vulkan {})",
        report.device, report.device_index, report.device_type, report.api_version
    );
    println!("profile:   {}", report.profile);
    println!(
        "enabled:   occlusionQueryPrecise={} pipelineStatisticsQuery={} (profiling only; not in the baseline)",
        info.features.occlusion_query_precise, info.features.pipeline_statistics_query
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
    println!("\nscenes:     {}", report.scenes.join(", "));
    println!("techniques: {}", report.techniques.join(", "));
    Ok(())
}

fn bench(frame: &FrameArgs, warmup: u32, runs: u32, json: bool) -> Result<()> {
    use crate::frame::StencilMode;
    use crate::profile::bench::{self, BenchReport, BenchSettings, Variant};
    use crate::technique::shadow_volume::ShadowVolumeRenderer;

    if runs == 0 {
        return Err(Error::InvalidInput("--runs must be at least 1".into()));
    }
    let options = options(frame)?;
    let scene = load_scene(&frame.scene, frame.time)?;
    let gpu = open_gpu(&frame.gpu)?;
    let (width, height) = (options.width, options.height);
    let mut variants = Vec::new();
    match options.technique {
        Technique::ShadowVolume => {
            let mut reference =
                ShadowVolumeRenderer::new(&gpu, &scene, width, height, StencilMode::Reference, &options.shadow_volume)?;
            variants.push(Variant {
                name: "reference (stencil)".into(),
                frame: Box::new(move || Ok(reference.frame()?.output)),
            });
            for normalize in Normalize::ALL {
                let sv = ShadowVolumeOptions { normalize, ..options.shadow_volume };
                let mut renderer = ShadowVolumeRenderer::new(&gpu, &scene, width, height, StencilMode::Emulated, &sv)?;
                variants.push(Variant {
                    name: format!("emulated {}", normalize.name()),
                    frame: Box::new(move || Ok(renderer.frame()?.output)),
                });
            }
        }
        Technique::Lit => {
            for stencil in [StencilMode::Reference, StencilMode::Emulated] {
                let opts = RenderOptions { stencil, ..options.clone() };
                let (gpu, scene) = (gpu.clone(), &scene);
                variants.push(Variant {
                    name: format!("lit ({})", stencil.name()),
                    frame: Box::new(move || Ok(render_scene(&gpu, scene, &opts)?.output)),
                });
            }
        }
    }
    let results = bench::run(variants, &BenchSettings { warmup, runs, progress: !json })?;
    let report = BenchReport {
        schema: "nostencil-bench/1",
        device: gpu.device.info.name.clone(),
        technique: options.technique.name().into(),
        scene: scene.name.clone(),
        width,
        height,
        warmup,
        runs,
        variants: results,
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&report).map_err(|e| Error::InvalidInput(e.to_string()))?);
    } else {
        print!("{}", report.table());
    }
    Ok(())
}

fn view(
    frame: &FrameArgs,
    frames: Option<u32>,
    screenshot: Option<std::path::PathBuf>,
    resize_after: Option<Vec<String>>,
    paused: bool,
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
    let resize_after = match resize_after.as_deref() {
        None => None,
        Some([after, size]) => {
            let after: u32 = after.parse().map_err(|_| {
                Error::InvalidInput(format!("--resize-after {after}: expected a frame count, such as 3"))
            })?;
            Some((after, super::args::parse_size(size)?))
        }
        Some(_) => return Err(Error::InvalidInput("--resize-after takes a frame count and WxH".into())),
    };
    let options = options(frame)?;
    let scene = load_scene(&frame.scene, frame.time)?;
    let device = frame.gpu.device.as_deref().map(DeviceChoice::parse).unwrap_or_default();
    crate::viewer::run(
        ViewerOptions {
            settings: Settings {
                technique: options.technique,
                stencil: options.stencil,
                shadow_volume: options.shadow_volume,
            },
            size: frame.size,
            gpu: GpuOptions { validation: frame.gpu.validation, device },
            frames,
            screenshot,
            resize_after,
            paused,
        },
        scene,
    )
}
