//! `nostencil profile`: one frame of this crate's, measured pass by pass, with the outputs
//! asked for: heat map, chart, trace, budget (checked or recorded), JUnit XML, the HTML page.

use std::path::PathBuf;
use std::sync::Arc;

use super::args::FrameArgs;
use super::frame_setup::{load_scene, open_gpu, options, print_warnings};
use super::output_path::check_output_path;
use crate::error::{Error, Result};
use crate::frame::render_pass::COLOUR_FORMAT;
use crate::frame::targets::choose_depth_format;
use crate::gpu::Gpu;
use crate::profile::budget::Budget;
use crate::profile::report::{FrameFormats, ProfileReport, ReportContext, ReportFormat};
use crate::scene::Scene;
use crate::technique::{render_scene, RenderOptions};

pub struct ProfileOutputs {
    pub heatmap: Option<PathBuf>,
    pub chart: Option<PathBuf>,
    pub budget: Option<PathBuf>,
    pub record_budget: Option<PathBuf>,
    /// The run's page (`--html`).
    pub html: Option<PathBuf>,
    /// The budget's verdict as JUnit XML (`--junit`, with `--budget`).
    pub junit: Option<PathBuf>,
    pub trace: Option<PathBuf>,
    pub move_model: Option<String>,
    /// `--caster-fill N`: the N casters spending most of the volume fill.
    pub caster_fill: Option<u32>,
}

/// The steady frame of `scene` after object `name` moved by 1% of the scene's size along x,
/// rendered by the renderer that drew it before the move (`profile --move-model`).
fn render_after_a_move(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    options: &RenderOptions,
    name: &str,
) -> Result<crate::technique::TechniqueFrame> {
    let index = scene.objects.iter().position(|o| o.name == name).ok_or_else(|| {
        let names: Vec<&str> = scene.objects.iter().take(12).map(|o| o.name.as_str()).collect();
        let more = if scene.objects.len() > names.len() { ", ..." } else { "" };
        Error::InvalidInput(format!(
            "--move-model '{name}': scene '{}' has no object of that name (it has {}{more})",
            scene.name,
            names.join(", ")
        ))
    })?;
    let corners = scene.objects.iter().map(|o| o.transform.w_axis.truncate());
    let size = crate::scene::bounds_of(corners).map_or(1.0, |(lo, hi)| (hi - lo).length().max(1.0));
    let mut moved = scene.clone();
    let step = glam::Mat4::from_translation(glam::Vec3::X * (0.01 * size));
    moved.objects[index].transform = step * moved.objects[index].transform;
    let mut renderer = options.technique.build(gpu, scene, options)?;
    for _ in 0..renderer.frames_to_steady_state() {
        renderer.frame_with(scene)?;
    }
    renderer.frame_with(&moved)
}

pub fn profile(frame: &FrameArgs, format: ReportFormat, outputs: &ProfileOutputs) -> Result<()> {
    let written =
        [&outputs.heatmap, &outputs.chart, &outputs.record_budget, &outputs.trace, &outputs.html, &outputs.junit];
    for path in written.into_iter().flatten() {
        check_output_path(path)?;
    }
    let options = options(frame)?;
    let scene = load_scene(frame)?;
    let gpu = open_gpu(&frame.gpu)?;
    // One frame first: llvmpipe compiles shaders at first draw, which is not the frame's cost.
    render_scene(&gpu, &scene, &options)?;
    let frame_result = match &outputs.move_model {
        None => render_scene(&gpu, &scene, &options)?,
        Some(name) => render_after_a_move(&gpu, &scene, &options, name)?,
    };
    print_warnings(options.technique.name(), &frame_result.warnings);
    let output = &frame_result.output;
    let (technique, stencil) = (options.technique.name(), options.stencil.name());
    let mut report = ProfileReport::new(
        ReportContext {
            device: gpu.device.info.name.clone(),
            scene: scene.name.clone(),
            technique: technique.into(),
            stencil: stencil.into(),
            frame_formats: FrameFormats {
                colour: format!("{COLOUR_FORMAT:?}"),
                depth: format!("{:?}", choose_depth_format(&gpu, options.stencil)?),
            },
        },
        &output.counters,
    );
    let mut stats = frame_result.stats.json();
    let caster_fill = match outputs.caster_fill {
        Some(top) => Some(crate::profile::caster_fill::measure(&gpu, &scene, &options, &frame_result, top as usize)?),
        None => None,
    };
    if let (Some(fill), Some(object)) = (&caster_fill, stats.as_object_mut()) {
        object.insert("caster_fill".into(), serde_json::to_value(fill).map_err(|e| Error::Internal(e.to_string()))?);
    }
    // The volumes' area, from one more frame of the same scene (not of a moved one).
    let coverage = match outputs.move_model {
        None => crate::profile::volume_coverage::measure(&gpu, &scene, &options, &frame_result)?,
        Some(_) => None,
    };
    if let (Some(coverage), Some(object)) = (&coverage, stats.as_object_mut()) {
        let value = serde_json::to_value(coverage).map_err(|e| Error::Internal(e.to_string()))?;
        object.insert("volume_coverage".into(), value);
    }
    report.technique_stats = (!stats.is_null()).then_some(stats);
    print!("{}", report.render(format));
    let lines = frame_result.stats.report();
    if format == ReportFormat::Table && !lines.is_empty() {
        println!("\n{lines}");
    }
    if format == ReportFormat::Table {
        match (&coverage, &outputs.move_model) {
            (Some(coverage), _) => print!("\n{}", crate::profile::volume_coverage::table(coverage)),
            // Said, not left out unsaid: the probe redraws the scene as loaded.
            (None, Some(_)) if frame_result.stats::<crate::technique::ShadowVolumeStats>().is_some() => {
                println!("\nshadow volumes' area: not measured with --move-model");
            }
            _ => {}
        }
    }
    if let (Some(fill), ReportFormat::Table) = (&caster_fill, format) {
        print!("\n{}", crate::profile::caster_fill::table(fill));
    }

    // The heat map: for its file, and for the page.
    let heatmap = match (&outputs.heatmap, &outputs.html) {
        (None, None) => None,
        _ => {
            let counting = RenderOptions { count_overdraw: true, ..options.clone() };
            let counted = render_scene(&gpu, &scene, &counting)?;
            Some(crate::profile::heatmap::render_heatmap(&counted.output.image))
        }
    };
    if let (Some(path), Some(image)) = (&outputs.heatmap, &heatmap) {
        crate::frame::write_png(image, path, false)?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &outputs.trace {
        let process = format!("nostencil profile: {technique} ({stencil}) on {}", scene.name);
        let mut trace = crate::profile::trace::Trace::new(&process, true);
        trace.own_frame(technique, 0, 0.0, &output.counters);
        trace.write(path)?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &outputs.chart {
        let title = format!("{technique} ({stencil}) on {}, {}x{}", scene.name, options.width, options.height);
        let svg = crate::profile::chart::bar_chart_svg(&title, &output.counters);
        crate::frame::write_atomically(path, svg.as_bytes())?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(path) = &outputs.record_budget {
        Budget::from_frame(&scene.name, technique, stencil, &output.counters).write(path)?;
        eprintln!("wrote budget {}", path.display());
    }
    let figures = match &outputs.budget {
        Some(path) => Some(Budget::load(path)?.compared(&scene.name, technique, stencil, &output.counters)?),
        None => None,
    };
    let budget_file = outputs.budget.as_ref().map(|p| p.display().to_string());
    let verdict = budget_file.as_deref().zip(figures.as_deref());
    if let (Some(path), Some((file, figures))) = (&outputs.junit, verdict) {
        let suite = format!("{technique} ({stencil}) on {}", scene.name);
        crate::profile::junit::write(path, &suite, file, figures)?;
    }
    if let Some(path) = &outputs.html {
        let png = match &heatmap {
            Some(image) => Some(crate::frame::png::encode_png(image, false)?),
            None => None,
        };
        let extras = crate::profile::html::from_profile::ProfileExtras {
            budget: verdict,
            heatmap: png,
            technique_lines: lines.clone(),
            json: report.render(ReportFormat::Json),
        };
        crate::profile::html::from_profile::profile_page(&report, extras).write(path)?;
    }
    if let (Some(path), Some(figures)) = (&outputs.budget, &figures) {
        let overruns: Vec<_> = figures.iter().filter(|f| f.over()).collect();
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
