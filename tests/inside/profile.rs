//! The fill-rate profiler: counters add up, the heat map counts what it claims, budgets catch a
//! costlier frame, and every output format says the same thing.

use crate::common;

use std::sync::Arc;

use glam::Vec4;
use nostencil::frame::FrameTargets;
use nostencil::pipeline::{FixedFunction, PipelineDesc, VertexLayout};
use nostencil::profile::budget::{Budget, BudgetFigure};
use nostencil::profile::heatmap;
use nostencil::profile::report::{FrameFormats, ProfileReport, ReportContext};
use nostencil::render::Renderer;
use nostencil::render::{Pipeline, PipelineTarget};
use nostencil::FrameOutput;
use nostencil::Gpu;
use nostencil::StencilMode;

/// A frame of `passes`, each drawing `quads` full-screen triangles, counted or not.
fn stacked_fullscreen(gpu: &Arc<Gpu>, passes: &[(&str, u32)], count_overdraw: bool) -> FrameOutput {
    stacked_fullscreen_at(gpu, passes, count_overdraw, 1)
}

/// As `stacked_fullscreen`, with `samples` samples per pixel.
fn stacked_fullscreen_at(gpu: &Arc<Gpu>, passes: &[(&str, u32)], count_overdraw: bool, samples: u32) -> FrameOutput {
    let targets =
        FrameTargets::with_samples(gpu, 96, 64, StencilMode::Emulated, false, samples, false).expect("targets");
    let mut renderer = Renderer::with_targets(gpu, targets).expect("renderer");
    renderer.count_overdraw = count_overdraw;
    let desc = PipelineDesc {
        name: "full-screen",
        vertex_shader: nostencil::shaders::FULLSCREEN_VERT,
        fragment_shader: nostencil::shaders::SOLID_FRAG,
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction::FULLSCREEN,
        push_constant_bytes: 16,
    };
    let target =
        PipelineTarget { render_pass: renderer.targets.render_pass, colour_attachments: 1, samples, lights: 1 };
    let pipeline = Pipeline::for_target(gpu, &desc, target, &[]).expect("pipeline");
    let uniforms = common::clip_space_uniforms();
    renderer
        .render(&uniforms, [0.0, 0.0, 0.0, 1.0], |rec| {
            for (name, quads) in passes {
                rec.pass(name, |rec| {
                    rec.bind(&pipeline);
                    rec.push(&pipeline, &Vec4::new(0.2, 0.4, 0.6, 1.0));
                    for _ in 0..*quads {
                        rec.draw(3, 1, 0, 0);
                    }
                    Ok(())
                })?;
            }
            Ok(())
        })
        .expect("frame")
}

#[test]
fn heat_map_of_n_stacked_fullscreen_quads_shows_n_everywhere() {
    let gpu = common::gpu();
    for n in [1u32, 3, 7] {
        let frame = stacked_fullscreen(&gpu, &[("stack", n)], true);
        let counts = heatmap::counts(&frame.image);
        assert!(counts.iter().all(|&c| c as u32 == n), "{n} quads: counts {:?}", &counts[..4]);
        let map = heatmap::render_heatmap(&frame.image);
        assert_eq!(map.get_pixel(10, 10).0[..3], heatmap::colour_of(n as u8));
        assert_eq!(frame.counters.passes[0].samples_passed, 96 * 64 * n as u64);
    }
    common::assert_no_validation_messages(&gpu);
}

/// At 4 samples the counter is blended in every sample and resolved (the mean of the pixel's
/// samples): n full-screen quads still read n, while the occlusion query counts every sample and
/// the overdraw divides by them.
#[test]
fn heat_map_and_overdraw_of_full_screen_quads_are_the_same_at_four_samples() {
    let gpu = common::gpu();
    for n in [1u32, 3, 7] {
        let frame = stacked_fullscreen_at(&gpu, &[("stack", n)], true, 4);
        let counts = heatmap::counts(&frame.image);
        assert!(counts.iter().all(|&c| c as u32 == n), "{n} quads at 4x: counts {:?}", &counts[..4]);
        let map = heatmap::render_heatmap(&frame.image);
        assert_eq!(map.get_pixel(10, 10).0[..3], heatmap::colour_of(n as u8));
        let counted = stacked_fullscreen_at(&gpu, &[("stack", n)], false, 4).counters;
        assert_eq!(counted.samples, 4);
        assert_eq!(counted.passes[0].samples_passed, 4 * 96 * 64 * n as u64);
        assert_eq!(counted.overdraw(), n as f64);
        let context = ReportContext {
            device: "test".into(),
            scene: "full-screen".into(),
            technique: "stack".into(),
            stencil: "emulated".into(),
            frame_formats: FrameFormats { colour: "c".into(), depth: "d".into() },
        };
        let report = ProfileReport::new(context, &counted);
        assert_eq!((report.samples, report.passes[0].samples_per_pixel), (4, n as f64));
        assert_eq!(report.totals.overdraw, n as f64);
        // Fragment shading stays per pixel: one invocation covers all four samples.
        let single = stacked_fullscreen_at(&gpu, &[("stack", n)], false, 1).counters;
        assert_eq!(counted.total_fragment_invocations(), single.total_fragment_invocations());
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn frame_totals_are_the_sum_of_the_passes() {
    let gpu = common::gpu();
    let frame = stacked_fullscreen(&gpu, &[("a", 1), ("b", 2), ("c", 4)], false);
    let c = &frame.counters;
    assert_eq!(c.total_samples_passed(), c.passes.iter().map(|p| p.samples_passed).sum::<u64>());
    assert_eq!(c.total_samples_passed(), 96 * 64 * 7);
    assert!((c.overdraw() - 7.0).abs() < 1e-9);
    assert_eq!(c.total_fragment_invocations(), c.passes.iter().map(|p| p.fragment_invocations).sum::<Option<u64>>());
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn budget_fails_on_a_costlier_pass_and_passes_on_the_recorded_frame() {
    let gpu = common::gpu();
    let cheap = stacked_fullscreen(&gpu, &[("scene", 1), ("overlay", 1)], false);
    let budget = Budget::from_frame("test", "stack", "emulated", &cheap.counters);
    let over = |counters| -> Vec<BudgetFigure> {
        let figures = budget.compared("test", "stack", "emulated", counters).expect("comparable");
        figures.into_iter().filter(BudgetFigure::over).collect()
    };
    assert!(over(&cheap.counters).is_empty(), "the same frame is within its budget");
    // More overdraw in one pass: exactly that pass is named.
    let costly = stacked_fullscreen(&gpu, &[("scene", 1), ("overlay", 3)], false);
    let overruns = over(&costly.counters);
    assert!(!overruns.is_empty());
    // ...and the frame's bytes on an immediate-mode GPU (every passing sample read and written);
    // a tiler's stay: the overdraw never leaves tile memory.
    let (frame, passes): (Vec<_>, Vec<_>) = overruns.iter().partition(|o| o.pass == "frame");
    assert!(passes.iter().all(|o| o.pass == "overlay"), "{overruns:?}");
    assert!(overruns.iter().any(|o| o.counter == "samples passed" && o.actual == 3 * o.budget));
    let counters: Vec<&str> = frame.iter().map(|o| o.counter).collect();
    assert_eq!(counters, ["immediate-mode bytes per frame"], "{overruns:?}");
    // A 4x frame passes 4 times the samples: it is not compared with a 1x budget at all.
    let four = stacked_fullscreen_at(&gpu, &[("scene", 1), ("overlay", 1)], false, 4);
    let refused = budget.compared("test", "stack", "emulated", &four.counters).expect_err("4x frame, 1x budget");
    assert!(refused.to_string().contains("budget is for 1x MSAA, the frame has 4x"), "{refused}");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn budget_recipe_from_the_command_line() {
    let dir = common::scratch_dir("profile-budget");
    let budget = dir.join("budget.json");
    let b = budget.to_str().unwrap();
    let args = ["profile", "--technique", "shadow-volume", "--size", "96x64", "--format", "csv"];
    // `--write-budget`, profile's old name for `--record-budget`, still records one.
    common::run_ok(&[&args[..], &["--write-budget", b]].concat());
    common::run_ok(&[&args[..], &["--budget", b]].concat());

    // Tighten one pass's budget: the same frame is now "more expensive" than allowed.
    let mut recorded: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&budget).unwrap()).unwrap();
    let pass = recorded["passes"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|p| p["name"] == "sun: volumes (alpha, z-pass)")
        .unwrap();
    pass["samples_passed"] = serde_json::json!(pass["samples_passed"].as_u64().unwrap() / 2);
    std::fs::write(&budget, serde_json::to_string(&recorded).unwrap()).unwrap();
    let stderr = common::run_err(&[&args[..], &["--budget", b]].concat());
    assert!(stderr.contains("volumes (alpha, z-pass)") && stderr.contains("over the budget"), "{stderr}");
}

#[test]
fn json_matches_the_table_and_totals_add_up() {
    let args = ["profile", "--technique", "shadow-volume", "--size", "96x64"];
    let (json, _) = common::run_ok(&[&args[..], &["--format", "json"]].concat());
    let (table, _) = common::run_ok(&args);
    let report: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    let passes = report["passes"].as_array().unwrap();
    let sum = |key: &str| passes.iter().map(|p| p[key].as_u64().unwrap()).sum::<u64>();
    assert_eq!(report["totals"]["samples_passed"].as_u64().unwrap(), sum("samples_passed"));
    assert_eq!(report["totals"]["fragment_invocations"].as_u64().unwrap(), sum("fragment_invocations"));
    for pass in passes {
        let name = pass["name"].as_str().unwrap();
        let row = table.lines().find(|l| l.starts_with(name)).unwrap_or_else(|| panic!("{name} not in table"));
        assert!(row.contains(&pass["samples_passed"].to_string()), "{row}");
        assert!(row.contains(&pass["fragment_invocations"].to_string()), "{row}");
    }
    // The default frame (additive, seed) counts no saturation: it says so, and where it would.
    assert!(report["technique_stats"]["saturated_samples"].is_null());
    let measured_by = report["technique_stats"]["saturation_measured_by"].as_str().expect("saturation source");
    assert!(measured_by.contains("not measured") && measured_by.contains("subpass"), "{measured_by}");
    assert!(table.contains("saturated samples: not measured"), "{table}");
    assert!(!table.contains("saturation probe"), "{table}");
    // The frame's formats are named: sRGB colour, and a depth format with no stencil aspect.
    assert_eq!(report["frame_formats"]["colour"], "R8G8B8A8_SRGB");
    let depth = report["frame_formats"]["depth"].as_str().expect("depth format");
    assert!(!depth.contains("S8"), "emulated frame has no stencil: {depth}");
    assert!(table.lines().next().is_some_and(|l| l.contains("colour R8G8B8A8_SRGB depth D")), "{table}");
}

#[test]
fn saturation_is_reported_where_measured_and_the_probe_is_opt_in() {
    let args = ["profile", "--technique", "shadow-volume", "--size", "96x64", "--format", "json"];
    let stats = |extra: &[&str]| {
        let (json, _) = common::run_ok(&[&args[..], extra].concat());
        let report: serde_json::Value = serde_json::from_str(&json).expect("JSON");
        let names: Vec<String> =
            report["passes"].as_array().unwrap().iter().map(|p| p["name"].as_str().unwrap().to_owned()).collect();
        (report["technique_stats"].clone(), names)
    };
    let (subpass, names) = stats(&["--normalize", "subpass"]);
    assert_eq!(subpass["saturated_samples"], 0, "{subpass}");
    assert!(subpass["saturation_measured_by"].as_str().unwrap().contains("subpass mask"), "{subpass}");
    assert!(!names.iter().any(|n| n == "saturation probe"), "{names:?}");
    let (subpass, _) = stats(&["--normalize", "subpass", "--shadow-mode", "modulate"]);
    assert!(subpass["saturation_measured_by"].as_str().unwrap().contains("subpass apply"), "{subpass}");
    // The probe reads the seed's up-counter: the modulate mode's.
    let (probed, names) = stats(&["--normalize", "max", "--saturation-probe", "--shadow-mode", "modulate"]);
    assert!(names.iter().any(|n| n == "saturation probe"), "{names:?}");
    assert_eq!(probed["saturated_samples"], 0, "{probed}");
    assert_eq!(probed["probe_saturated_samples"], 0, "{probed}");
    let (reference, names) = stats(&["--stencil", "reference"]);
    assert!(reference["saturated_samples"].is_null(), "{reference}");
    assert_eq!(names, ["scene (ambient)", "sun: volumes (stencil, z-pass)", "sun: shading (stencil)", "transparent"]);
    let (_, names) = stats(&["--stencil", "reference", "--shadow-mode", "modulate"]);
    assert_eq!(names, ["scene", "volumes (stencil, z-pass)", "apply (stencil)"]);
    // The probe is never timed.
    let stderr = common::run_err(&["bench", "--technique", "shadow-volume", "--size", "32x32", "--saturation-probe"]);
    assert!(stderr.contains("--saturation-probe") && stderr.contains("never timed"), "{stderr}");
}

#[test]
fn heatmap_chart_compare_and_passes_from_the_command_line() {
    let dir = common::scratch_dir("profile-outputs");
    let heat = dir.join("heat.png");
    let chart = dir.join("chart.svg");
    common::run_ok(&[
        "profile",
        "--technique",
        "lit",
        "--size",
        "96x64",
        "--heatmap",
        heat.to_str().unwrap(),
        "--chart",
        chart.to_str().unwrap(),
    ]);
    let png = common::read_png(&heat);
    assert!(png.width() >= 96 && png.height() > 64);
    // The lit default scene, frame in the top-left 96x64: nothing is drawn in the sky's
    // corner (count 0), and the ground at the bottom centre was drawn at least once.
    let zero = heatmap::colour_of(0);
    assert_eq!(png.get_pixel(0, 0).0, zero, "the sky's corner was drawn");
    assert_ne!(png.get_pixel(48, 63).0, zero, "the ground was not drawn");
    let svg = std::fs::read_to_string(&chart).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains(">scene<"));

    let (text, _) = common::run_ok(&[
        "profile",
        "--technique",
        "shadow-volume",
        "--size",
        "96x64",
        "--compare",
        "reference,seed,subpass",
    ]);
    assert!(text.contains("ratio to reference") && text.contains("sun: mask (subpass)"), "{text}");

    let (text, _) = common::run_ok(&["passes", "--technique", "shadow-volume"]);
    // Every plan: both counting methods, each path; the seed's steps in order.
    for title in
        ["### reference, zpass", "### reference, zfail", "### emulated seed, zpass", "### emulated subpass, zfail"]
    {
        assert!(text.contains(title), "{title} missing:\n{text}");
    }
    assert!(text.contains("| sun: normalise N1 | normalise iteration |") && !text.contains("normalise N0"), "{text}");
    assert!(text.contains("| sun: shading | shading |"), "{text}");
    assert!(text.contains("DECREMENT_AND_WRAP"), "{text}");
    // The seed's frame, and the loop of a scene's lights.
    let (text, _) = common::run_ok(&["passes", "--technique", "shadow-volume", "--shadow-mode", "modulate"]);
    assert!(
        text.contains("| normalise N0 | normalise N0 |") && text.contains("| normalise N1 | normalise iteration |")
    );
    let (text, _) = common::run_ok(&["passes", "--technique", "shadow-volume", "--scene", "lights"]);
    for row in
        ["| sun: volumes (alpha, z-pass) |", "| lamp: normalise N1 |", "| spot: mask (subpass) |", "| spot: shading |"]
    {
        assert!(text.contains(row), "{row} missing:\n{text}");
    }
}

/// Every technique whose passes all draw into the frame: its heat map holds, summed over the
/// pixels, exactly the samples its passes' occlusion queries counted (the counter pipelines keep
/// each pipeline's depth test and replace only its blend), so no pass escapes the count.
#[test]
fn heat_map_sums_to_the_samples_every_technique_passed() {
    use nostencil::{render_scene, RenderOptions, TECHNIQUES};
    let gpu = common::gpu();
    let scene = nostencil::builtin_scene("default").expect("default scene");
    // Not the shadow texture, map, atlas and projective texture: their prepasses draw outside
    // the frame.
    let in_frame_only = TECHNIQUES.iter().copied().filter(|t| {
        !matches!(t.name(), "shadow-texture" | "shadow-map" | "shadow-texture-atlas" | "projective-texture")
    });
    for technique in in_frame_only {
        let options = RenderOptions { width: 96, height: 64, technique, count_overdraw: true, ..Default::default() };
        let frame = render_scene(&gpu, &scene, &options).expect("counted frame");
        let counts = heatmap::counts(&frame.output.image);
        assert!(counts.iter().all(|c| *c < 255), "{technique:?}: a count saturated");
        let summed: u64 = counts.iter().map(|c| *c as u64).sum();
        assert_eq!(summed, frame.output.counters.total_samples_passed(), "{technique:?}");
        assert!(summed > 96 * 64 / 2, "{technique:?}: only {summed} samples in 96x64");
    }
    common::assert_no_validation_messages(&gpu);
}

// The tests by topic, beside those above.
#[path = "profile/trace_and_fill.rs"]
mod trace_and_fill;
#[path = "profile/traffic_and_bandwidth.rs"]
mod traffic_and_bandwidth;
