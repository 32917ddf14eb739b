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
        subpass: 0,
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
                        rec.draw_fullscreen();
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

#[test]
fn tile_traffic_is_listed_per_render_pass_with_known_sizes() {
    // The frame alone: colour cleared and stored (W x H x 4 bytes), depth cleared, not stored.
    let json = |args: &[&str]| -> serde_json::Value {
        let (stdout, _) = common::run_ok(args);
        serde_json::from_str(&stdout).expect("JSON")
    };
    let lit = json(&["profile", "--size", "96x64", "--format", "json", "--samples", "1"]);
    assert_eq!(lit["samples"], 1);
    let passes = lit["render_passes"].as_array().expect("render_passes");
    assert_eq!(passes.len(), 1, "{passes:?}");
    assert_eq!((passes[0]["pass"].as_str(), passes[0]["count"].as_u64()), (Some("frame"), Some(1)));
    let frame = passes[0]["attachments"].as_array().expect("attachments");
    assert_eq!(frame.len(), 2, "{frame:?}");
    assert_eq!(frame[0]["bytes_stored"], 96 * 64 * 4);
    assert_eq!(frame[0]["bytes_loaded"], 0);
    assert_eq!(frame[1]["bytes_stored"], 0);
    assert!(frame.iter().all(|a| a["samples"] == 1), "{frame:?}");

    // The atlas with a moving light: the sun's shadow map (512^2 depth, stored), the page pass
    // over both tiles (its first: cleared in the pass and stored, 512x256), then the frame. Both of atlas-one's models
    // are baked by their texels (a geometry image and the ground, a quad mapped whole); with
    // `--atlas-bake rasterised` they are rasterised into the raw page first (512x256 stored).
    let atlas_args = |bake: &'static str| {
        [
            "profile",
            "--size",
            "96x64",
            "--format",
            "json",
            "--technique",
            "shadow-texture-atlas",
            "--scene",
            "atlas-one",
            "--light-motion",
            "moving",
            "--atlas-bake",
            bake,
        ]
    };
    let names_of = |report: &serde_json::Value| -> Vec<String> {
        let passes = report["render_passes"].as_array().cloned().unwrap_or_default();
        passes.iter().filter_map(|p| p["pass"].as_str().map(String::from)).collect()
    };
    assert_eq!(names_of(&json(&atlas_args("texels"))), ["sun: shadow map", "atlas page", "frame"]);
    let atlas = json(&atlas_args("rasterised"));
    let passes = atlas["render_passes"].as_array().expect("render_passes");
    assert_eq!(names_of(&atlas), ["sun: shadow map", "atlas bake", "atlas page", "frame"], "{passes:?}");
    let map = &passes[0];
    assert_eq!((map["width"].as_u64(), map["height"].as_u64()), (Some(512), Some(512)));
    let depth = &map["attachments"][0];
    let texel = if depth["format"] == "D16_UNORM" { 2 } else { 4 };
    assert_eq!(depth["bytes_stored"], 512 * 512 * texel);
    // atlas-one: the model and the ground, each a 256x256 tile of a 512x256 page, both
    // rasterised here.
    let bake = &passes[1];
    assert_eq!(
        (bake["width"].as_u64(), bake["height"].as_u64(), bake["count"].as_u64()),
        (Some(512), Some(256), Some(1))
    );
    assert_eq!(bake["attachments"][0]["bytes_stored"], 512 * 256 * 4);
    let page = &passes[2];
    assert_eq!((page["width"].as_u64(), page["height"].as_u64()), (Some(512), Some(256)));
    // The page's first update has nothing to keep: cleared in the pass, not loaded.
    assert_eq!(page["attachments"][0]["load_op"], "CLEAR");
    assert_eq!(page["attachments"][0]["bytes_loaded"], 0);
    assert_eq!(page["attachments"][0]["bytes_stored"], 512 * 256 * 4);

    // The planar render-texture shadow: its 128x128 texture under its own pass, not "frame".
    let planar = json(&["profile", "--size", "96x64", "--format", "json", "--technique", "shadow-texture"]);
    let passes = planar["render_passes"].as_array().expect("render_passes");
    let names: Vec<&str> = passes.iter().filter_map(|p| p["pass"].as_str()).collect();
    assert_eq!(names, ["shadow texture", "frame"], "{passes:?}");
    assert_eq!(passes[0]["attachments"][0]["bytes_stored"], 128 * 128 * 4);
}

/// The counters per render pass instance: the atlas with a moving light (`--atlas-bake
/// rasterised`) begins the shadow map, the raster bake, the page pass, then the frame, in that
/// order, one instance each however many models; each instance's sum is its passes', and the sums add up to the frame's totals.
#[test]
fn counters_are_summed_per_render_pass_instance_in_submission_order() {
    let args = ["profile", "--size", "96x64", "--format", "json", "--technique", "shadow-texture-atlas"];
    let rasterised = ["--scene", "atlas-one", "--light-motion", "moving", "--atlas-bake", "rasterised"];
    let (stdout, _) = common::run_ok(&[&args[..], &rasterised].concat());
    let report: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    let instances = report["render_pass_instances"].as_array().expect("render_pass_instances");
    let owners: Vec<&str> = instances.iter().map(|i| i["passes"][0].as_str().unwrap_or("?")).collect();
    // atlas-one, both models rasterised: one instance per pass all the same.
    assert_eq!(owners, ["sun: shadow map", "atlas bake", "atlas page", "scene"]);
    assert!(instances.iter().enumerate().all(|(i, inst)| inst["index"] == i as u64));
    let sums = report["render_pass_sums"].as_array().expect("render_pass_sums");
    let spans: Vec<(u64, u64)> =
        sums.iter().map(|s| (s["first"].as_u64().unwrap_or(99), s["count"].as_u64().unwrap_or(99))).collect();
    assert_eq!(spans, [(0, 1), (1, 1), (2, 1), (3, 1)]);
    let passes = report["passes"].as_array().expect("passes");
    let pass = |name: &str| passes.iter().find(|p| p["name"] == name).unwrap_or_else(|| panic!("no pass {name}"));
    for sum in sums {
        let names: Vec<&str> = sum["passes"].as_array().expect("names").iter().filter_map(|n| n.as_str()).collect();
        for counter in ["samples_passed", "fragment_invocations", "draws"] {
            let expected: u64 = names.iter().map(|n| pass(n)[counter].as_u64().unwrap_or(0)).sum();
            assert_eq!(sum[counter].as_u64(), Some(expected), "{counter} of {names:?}");
        }
    }
    // Every pass but the copy-only mip build drew into some instance.
    let summed: u64 = sums.iter().map(|s| s["samples_passed"].as_u64().unwrap_or(0)).sum();
    assert_eq!(Some(summed), report["totals"]["samples_passed"].as_u64());
    let named: Vec<&str> =
        sums.iter().flat_map(|s| s["passes"].as_array().into_iter().flatten()).filter_map(|n| n.as_str()).collect();
    let unnamed: Vec<&str> = passes.iter().filter_map(|p| p["name"].as_str()).filter(|n| !named.contains(n)).collect();
    assert!(unnamed.iter().all(|n| pass(n)["draws"] == 0), "passes outside every render pass drew: {unnamed:?}");
}

/// `profile --samples 4`: the frame's multisampled colour and depth are transient (cleared and
/// discarded in tile memory: 0 bytes loaded or stored) with 4 samples, and only the one-sample
/// resolve target is stored, W x H x 4 bytes; the table says the same as the JSON.
#[test]
fn tile_traffic_at_four_samples_stores_only_the_resolve_target() {
    let args = ["profile", "--size", "96x64", "--samples", "4", "--technique", "shadow-volume", "--validation"];
    let (stdout, err) = common::run_ok(&[&args[..], &["--format", "json"]].concat());
    assert!(!err.contains("vulkan validation"), "{err}");
    let report: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    assert_eq!(report["samples"], 4);
    let passes = report["render_passes"].as_array().expect("render_passes");
    assert_eq!(passes.len(), 1, "{passes:?}");
    let frame = passes[0]["attachments"].as_array().expect("attachments");
    let field = |a: &serde_json::Value, key: &str| a[key].as_str().unwrap_or_default().to_owned();
    let names: Vec<String> = frame.iter().map(|a| field(a, "attachment")).collect();
    assert_eq!(names, ["colour (multisampled)", "depth", "colour (resolved)"], "{frame:?}");
    for multisampled in &frame[..2] {
        assert_eq!(multisampled["samples"], 4, "{multisampled}");
        assert_eq!(multisampled["transient"], true, "{multisampled}");
        assert_eq!(
            (field(multisampled, "load_op"), field(multisampled, "store_op")),
            ("CLEAR".into(), "DONT_CARE".into())
        );
        assert_eq!((multisampled["bytes_loaded"].as_u64(), multisampled["bytes_stored"].as_u64()), (Some(0), Some(0)));
    }
    let resolve = &frame[2];
    assert_eq!((resolve["samples"].as_u64(), resolve["transient"].as_bool()), (Some(1), Some(false)));
    assert_eq!(field(resolve, "store_op"), "STORE");
    assert_eq!((resolve["bytes_loaded"].as_u64(), resolve["bytes_stored"].as_u64()), (Some(0), Some(96 * 64 * 4)));

    // Counters per frame sample: each pass's samples/px and the overdraw divide by W x H x 4.
    let frame_samples = 96.0 * 64.0 * 4.0;
    for pass in report["passes"].as_array().expect("passes") {
        assert_eq!(pass["samples"], 4, "{pass}");
        let per = pass["samples_passed"].as_f64().unwrap() / frame_samples;
        assert!((pass["samples_per_pixel"].as_f64().unwrap() - per).abs() < 1e-9, "{pass}");
    }
    let totals = &report["totals"];
    assert!(
        (totals["overdraw"].as_f64().unwrap() - totals["samples_passed"].as_f64().unwrap() / frame_samples).abs()
            < 1e-9
    );

    // A prepass draws into its own one-sample target: stored, and counted per pixel of it.
    let textured =
        ["profile", "--size", "96x64", "--samples", "4", "--technique", "shadow-texture", "--format", "json"];
    let (stdout, _) = common::run_ok(&textured);
    let report: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    let traffic = report["render_passes"].as_array().expect("render_passes");
    assert_eq!(traffic[0]["pass"], "shadow texture", "{traffic:?}");
    assert_eq!(traffic[0]["attachments"][0]["samples"], 1, "{traffic:?}");
    assert_eq!(traffic[0]["attachments"][0]["bytes_stored"], 128 * 128 * 4, "{traffic:?}");
    for pass in report["passes"].as_array().expect("passes") {
        let samples = if pass["name"] == "shadow texture" { 1 } else { 4 };
        assert_eq!(pass["samples"], samples, "{pass}");
        let per = pass["samples_passed"].as_f64().unwrap() / (96.0 * 64.0 * samples as f64);
        assert!((pass["samples_per_pixel"].as_f64().unwrap() - per).abs() < 1e-9, "{pass}");
    }

    let (table, _) = common::run_ok(&args);
    assert!(table.lines().next().is_some_and(|l| l.contains("| 4x MSAA |")), "{table}");
    let line = |name: &str| {
        table.lines().find(|l| l.trim_start().starts_with(name)).unwrap_or_else(|| panic!("no {name} row:\n{table}"))
    };
    let multisampled = line("colour (multisampled)");
    assert!(
        multisampled.contains(" 4 samples") && multisampled.contains("stored          0 B  (transient)"),
        "{multisampled}"
    );
    let depth = line("depth ");
    assert!(depth.contains(" 4 samples") && depth.contains("stored          0 B  (transient)"), "{depth}");
    let resolve = line("colour (resolved)");
    assert!(resolve.contains(" 1 samples") && resolve.contains(&format!("stored {:>10} B", 96 * 64 * 4)), "{resolve}");
    assert!(!resolve.contains("transient"), "{resolve}");
    assert!(table.contains(&format!("frame total: loaded 0 B, stored {} B", 96 * 64 * 4)), "{table}");
}

/// At 4 samples the heat map is the mean count over each pixel's samples: summed over the
/// pixels and times 4 it is the samples the passes' occlusion queries counted, to within the
/// rounding of the pixels whose samples differ (on edges, at most 1/2 each, times 4).
#[test]
fn heat_map_at_four_samples_is_the_per_pixel_mean_of_the_samples() {
    use nostencil::{render_scene, technique as by_name, RenderOptions};
    let gpu = common::gpu();
    let scene = nostencil::builtin_scene("default").expect("default scene");
    for name in ["lit", "shadow-volume", "planar"] {
        let technique = by_name(name).expect("technique");
        let options =
            RenderOptions { width: 96, height: 64, technique, count_overdraw: true, samples: 4, ..Default::default() };
        let frame = render_scene(&gpu, &scene, &options).expect("counted frame");
        let counts = heatmap::counts(&frame.output.image);
        let summed: u64 = counts.iter().map(|c| *c as u64).sum();
        let samples = frame.output.counters.total_samples_passed();
        // Edge pixels: where a neighbour's count differs.
        let (w, h) = (96usize, 64usize);
        let edges = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| {
                let c = counts[y * w + x];
                [(x.wrapping_sub(1), y), (x + 1, y), (x, y.wrapping_sub(1)), (x, y + 1)]
                    .iter()
                    .any(|&(nx, ny)| nx < w && ny < h && counts[ny * w + nx] != c)
            })
            .count() as u64;
        let difference = (4 * summed).abs_diff(samples);
        assert!(difference <= 2 * edges, "{name}: 4 x {summed} vs {samples} samples, {edges} edge pixels");
        assert!(summed > 96 * 64 / 2, "{name}: only {summed} in 96x64");
    }
    common::assert_no_validation_messages(&gpu);
}

/// The bandwidth estimates (frame/bandwidth.rs, after Mesa turnip) of one frame at 1 and 4
/// samples, against figures computed here by hand from the attachments and the samples passed:
/// on a tiler the 4x frame moves what the 1x one does (its samples stay in tile memory; only
/// the resolve is stored), on an immediate-mode GPU about 4x as much.
#[test]
fn bandwidth_estimates_match_hand_computed_figures_at_one_and_four_samples() {
    let (width, height) = (96u64, 64u64);
    let pixels = width * height;
    let frame = |samples: &str| -> serde_json::Value {
        let args = ["profile", "--size", "96x64", "--samples", samples, "--technique", "shadow-volume"];
        let (stdout, _) = common::run_ok(&[&args[..], &["--format", "json"]].concat());
        serde_json::from_str(&stdout).expect("JSON")
    };
    let (one, four) = (frame("1"), frame("4"));
    let depth_bytes = |report: &serde_json::Value| match report["frame_formats"]["depth"].as_str() {
        Some("D16_UNORM") => 2,
        Some("D32_SFLOAT" | "X8_D24_UNORM_PACK32" | "D24_UNORM_S8_UINT") => 4,
        Some("D32_SFLOAT_S8_UINT") => 5,
        other => panic!("depth format {other:?}"),
    };
    let u64_of = |v: &serde_json::Value| v.as_u64().unwrap_or_else(|| panic!("not a number: {v}"));
    for report in [&one, &four] {
        assert_eq!(report["render_passes"].as_array().map(Vec::len), Some(1), "one render pass: {report}");
    }
    let colour = 4u64; // R8G8B8A8_SRGB
                       // 1x: colour cleared and stored, depth cleared and dropped; every passing sample reads and
                       // writes the colour and the depth.
    let (depth, samples_one) = (depth_bytes(&one), u64_of(&one["totals"]["samples_passed"]));
    let tiler_one = pixels * colour;
    let immediate_one = pixels * (colour + depth) + samples_one * 2 * (colour + depth);
    assert_eq!(u64_of(&one["totals"]["tiler_bytes"]), tiler_one);
    assert_eq!(u64_of(&one["totals"]["immediate_bytes"]), immediate_one);
    // 4x: both cleared at 4 samples and dropped; the colour resolved (4 samples read, 1 written)
    // into the one-sample target, the only store.
    let samples_four = u64_of(&four["totals"]["samples_passed"]);
    let tiler_four = pixels * colour;
    let immediate_four = pixels * 4 * (colour + depth) + pixels * colour * 5 + samples_four * 2 * (colour + depth);
    assert_eq!(u64_of(&four["totals"]["tiler_bytes"]), tiler_four);
    assert_eq!(u64_of(&four["totals"]["immediate_bytes"]), immediate_four);
    // The render pass's own figures are the frame's (one render pass).
    assert_eq!(u64_of(&four["render_pass_sums"][0]["immediate_bytes"]), immediate_four);
    let tiler_ratio = tiler_four as f64 / tiler_one as f64;
    let immediate_ratio = immediate_four as f64 / immediate_one as f64;
    assert!((tiler_ratio - 1.0).abs() < 0.03, "tiler 4x / 1x = {tiler_ratio}");
    assert!((3.5..=5.0).contains(&immediate_ratio), "immediate 4x / 1x = {immediate_ratio}");
    eprintln!(
        "bandwidth 96x64 shadow-volume: 1x tiler {tiler_one} B immediate {immediate_one} B; \
         4x tiler {tiler_four} B immediate {immediate_four} B (ratio {immediate_ratio:.2})"
    );
}

/// A CSV row's render pass instances, tiler bytes and immediate-mode bytes.
type CsvBytes = (Vec<u64>, u64, u64);

/// `profile ARGS` as JSON and as CSV; checks the CSV's header and that its bandwidth columns
/// are the JSON passes' and sum to the JSON's per-frame and per-group figures. Returns the rows'
/// bandwidth columns and the JSON's `render_pass_sums`.
fn csv_bytes_against_json(args: &[&str]) -> (Vec<CsvBytes>, Vec<serde_json::Value>) {
    let (json, _) = common::run_ok(&[args, &["--format", "json"]].concat());
    let (csv, _) = common::run_ok(&[args, &["--format", "csv"]].concat());
    let report: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some(
            "pass,draws,vertex_invocations,clipping_primitives,fragment_invocations,fragments_per_pixel,\
             samples_passed,samples_per_pixel,gpu_ms,share,render_pass_instances,tiler_bytes,immediate_bytes"
        )
    );
    // The last three fields, which hold no comma (a pass's name may).
    let rows: Vec<CsvBytes> = lines
        .map(|line| {
            let fields: Vec<&str> = line.rsplitn(4, ',').collect();
            let number = |f: &str| f.parse::<u64>().unwrap_or_else(|e| panic!("{f:?} in {line}: {e}"));
            (fields[2].split_whitespace().map(number).collect(), number(fields[1]), number(fields[0]))
        })
        .collect();
    let u64_of = |v: &serde_json::Value| v.as_u64().unwrap_or_else(|| panic!("not a number: {v}"));
    let passes = report["passes"].as_array().expect("passes");
    assert_eq!(rows.len(), passes.len(), "{csv}");
    for (row, pass) in rows.iter().zip(passes) {
        let instances = pass["render_pass_instances"].as_array().expect("instances").iter().map(u64_of).collect();
        assert_eq!(row, &(instances, u64_of(&pass["tiler_bytes"]), u64_of(&pass["immediate_bytes"])));
    }
    let column = |rows: &[&CsvBytes]| rows.iter().fold((0, 0), |(t, i), r| (t + r.1, i + r.2));
    let all: Vec<&CsvBytes> = rows.iter().collect();
    let totals = &report["totals"];
    assert_eq!(column(&all), (u64_of(&totals["tiler_bytes"]), u64_of(&totals["immediate_bytes"])), "{csv}");
    let sums = report["render_pass_sums"].as_array().expect("render_pass_sums").clone();
    for sum in &sums {
        let span = u64_of(&sum["first"])..u64_of(&sum["first"]) + u64_of(&sum["count"]);
        let members: Vec<&CsvBytes> = rows.iter().filter(|r| r.0.iter().any(|i| span.contains(i))).collect();
        assert_eq!(column(&members), (u64_of(&sum["tiler_bytes"]), u64_of(&sum["immediate_bytes"])), "{sum}");
    }
    (rows, sums)
}

/// `profile --format csv`: each pass's row names the render pass instances it drew into and
/// carries its part of the frame's bytes, so that the columns sum to the JSON's per-frame
/// figures and each group of instances' rows to that group's own. Two frames: shadow textures
/// (a prepass, then two passes in the frame's render pass) and the atlas with a moving light,
/// rasterised (shadow map, raster bake, page, frame, and a mip build that only copies).
#[test]
fn csv_bandwidth_columns_sum_to_the_jsons_frame_figures() {
    let texture = ["profile", "--size", "96x64", "--technique", "shadow-texture"];
    let (_, sums) = csv_bytes_against_json(&texture);
    let shared = sums.iter().find(|s| s["passes"].as_array().is_some_and(|p| p.len() > 1));
    assert!(sums.len() == 2 && shared.is_some(), "a prepass, then two passes in one instance: {sums:?}");
    let atlas = ["profile", "--size", "96x64", "--technique", "shadow-texture-atlas", "--scene", "atlas-one"];
    let moving = ["--light-motion", "moving", "--atlas-bake", "rasterised"];
    let (rows, sums) = csv_bytes_against_json(&[&atlas[..], &moving].concat());
    assert_eq!(sums.len(), 4, "{sums:?}");
    // The mip build drew into no render pass: no instance, no bytes.
    assert!(rows.iter().any(|r| r.0.is_empty() && r.1 == 0 && r.2 == 0), "{rows:?}");
}

/// The trace-event JSON's schema (ui.perfetto.dev and chrome://tracing open it): `traceEvents`,
/// complete events (`ph` "X") with `ts` and `dur` in microseconds, counter events (`ph` "C"),
/// process and thread names; every event has `pid` and `tid`.
fn trace_events(path: &std::path::Path) -> Vec<serde_json::Value> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let trace: serde_json::Value = serde_json::from_str(&text).expect("the trace is JSON");
    let events = trace["traceEvents"].as_array().expect("traceEvents").clone();
    for e in &events {
        assert!(e["pid"].is_u64() && e["tid"].is_u64() && e["name"].is_string(), "{e}");
        match e["ph"].as_str() {
            Some("X") => assert!(
                e["ts"].as_f64().is_some_and(|t| t >= 0.0) && e["dur"].as_f64().is_some_and(|d| d >= 0.0),
                "{e}"
            ),
            Some("C") => assert!(e["ts"].is_number() && e["args"].is_object(), "{e}"),
            Some("M") => assert!(["process_name", "thread_name"].contains(&e["name"].as_str().unwrap_or("")), "{e}"),
            other => panic!("unexpected phase {other:?}: {e}"),
        }
    }
    let named = |name: &str, tid: u64| events.iter().any(|e| e["ph"] == "M" && e["name"] == name && e["tid"] == tid);
    assert!(named("process_name", 0) && named("thread_name", 1), "process and GPU track named");
    events
}

/// `profile --trace`: one GPU slice per pass, its duration the report's GPU time in
/// microseconds; the CPU's record, submit and wait on their own track; the frame's counters
/// equal the report's totals. `bench --trace`: every frame it rendered, each with its CPU phases.
#[test]
fn the_trace_has_a_slice_per_pass_with_the_reports_gpu_times_and_its_counters() {
    let dir = common::scratch_dir("profile_trace");
    let path = dir.join("trace.json");
    let path_arg = path.to_string_lossy().into_owned();
    let args = ["profile", "--size", "96x64", "--technique", "shadow-volume", "--format", "json", "--trace", &path_arg];
    let (stdout, _) = common::run_ok(&args);
    let report: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    let events = trace_events(&path);
    assert!(events.iter().any(|e| e["ph"] == "M" && e["name"] == "thread_name" && e["tid"] == 2), "CPU track named");
    let gpu: Vec<&serde_json::Value> = events.iter().filter(|e| e["ph"] == "X" && e["tid"] == 1).collect();
    let passes = report["passes"].as_array().expect("passes");
    assert_eq!(gpu.len(), passes.len(), "one slice per pass");
    for (slice, pass) in gpu.iter().zip(passes) {
        assert_eq!(slice["name"], pass["name"]);
        let (dur, ms) = (slice["dur"].as_f64().unwrap_or(-1.0), pass["gpu_ms"].as_f64().unwrap_or(-2.0));
        assert!((dur - ms * 1e3).abs() < 1e-6 * dur.max(1.0), "{slice} against {pass}");
    }
    // Laid out from the timestamps: in order, none before the previous one began.
    assert!(gpu.windows(2).all(|w| w[1]["ts"].as_f64() >= w[0]["ts"].as_f64()));
    let cpu: Vec<&str> =
        events.iter().filter(|e| e["ph"] == "X" && e["tid"] == 2).filter_map(|e| e["name"].as_str()).collect();
    assert_eq!(cpu, ["record", "submit", "wait"]);
    let counter = |name: &str, series: &str| {
        let found = events.iter().find(|e| e["ph"] == "C" && e["name"] == name);
        found.map(|e| e["args"][series].clone()).unwrap_or_else(|| panic!("counter {name}"))
    };
    let totals = &report["totals"];
    assert_eq!(counter("samples", "samples passed"), totals["samples_passed"]);
    assert_eq!(counter("bytes", "tiler"), totals["tiler_bytes"]);
    assert_eq!(counter("bytes", "immediate-mode"), totals["immediate_bytes"]);
    if totals["fragment_invocations"].is_u64() {
        assert_eq!(counter("fragments", "fragments"), totals["fragment_invocations"]);
    }

    let bench_path = dir.join("bench.json");
    let bench_arg = bench_path.to_string_lossy().into_owned();
    let bench = ["bench", "--technique", "lit", "--size", "32x32", "--samples", "1", "--warmup", "1", "--runs", "2"];
    let (stdout, _) = common::run_ok(&[&bench[..], &["--json", "--trace", &bench_arg]].concat());
    let report: serde_json::Value = serde_json::from_str(&stdout).expect("bench JSON");
    let variants = report["variants"].as_array().map_or(0, Vec::len);
    let events = trace_events(&bench_path);
    let waits = events.iter().filter(|e| e["ph"] == "X" && e["name"] == "wait").count();
    assert_eq!(waits, variants * 3, "one frame per variant and round, the warm-up round too");
    let samples = events.iter().filter(|e| e["ph"] == "C" && e["name"] == "samples").count();
    assert_eq!(samples, waits, "counters per frame");
}

/// `profile --caster-fill`: each caster's volumes drawn alone, with the frame's counters. The
/// volumes are independent draws, so the casters' fragments and samples add up to the frame's
/// volume passes exactly; each light's fill and floor in the technique stats are those passes'
/// own counters per pixel; the top list is sorted; another technique is refused by name.
#[test]
fn caster_fill_adds_up_to_the_volume_passes_and_lights_report_their_fill() {
    let args = "profile --technique shadow-volume --scene lights --size 64x48 --samples 1 --format json \
                --caster-fill 99 --validation";
    let (out, err) = common::run_ok(&args.split_whitespace().collect::<Vec<_>>());
    assert!(!err.contains("vulkan validation"), "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    let volume_passes: Vec<&serde_json::Value> = report["passes"]
        .as_array()
        .expect("passes")
        .iter()
        .filter(|p| p["name"].as_str().is_some_and(|n| n.contains("volumes")))
        .collect();
    let sum = |key: &str| volume_passes.iter().map(|p| p[key].as_u64().expect(key)).sum::<u64>();
    let stats = &report["technique_stats"];
    let fills = stats["caster_fill"].as_array().expect("caster_fill");
    assert_eq!(fills.len(), stats["casters"].as_array().map_or(0, Vec::len), "every caster listed with 99");
    let fragments: Vec<u64> = fills.iter().map(|f| f["fragments"].as_u64().expect("fragments")).collect();
    assert!(fragments.windows(2).all(|w| w[0] >= w[1]), "sorted: {fragments:?}");
    assert_eq!(fragments.iter().sum::<u64>(), sum("fragment_invocations"), "{stats}");
    let samples: u64 = fills.iter().map(|f| f["samples_passed"].as_u64().expect("samples")).sum();
    assert_eq!(samples, sum("samples_passed"));
    let pixels = 64.0 * 48.0;
    let lights = stats["lights"].as_array().expect("lights");
    assert_eq!(lights.len(), 3);
    let fill: f64 = lights.iter().map(|l| l["volume_fill"].as_f64().expect("fill")).sum();
    let floor: f64 = lights.iter().map(|l| l["volume_samples_passed"].as_f64().expect("floor")).sum();
    assert!((fill * pixels - sum("fragment_invocations") as f64).abs() < 0.5, "{fill}");
    assert!((floor * pixels - sum("samples_passed") as f64).abs() < 0.5, "{floor}");
    // The volumes' area, from the same frame drawn again with their depth test off: at least
    // the samples that pass, each light beside its own fill and floor.
    let coverage = stats["volume_coverage"].as_array().expect("volume_coverage");
    assert_eq!(coverage.len(), 3, "{stats}");
    for (light, area) in lights.iter().zip(coverage) {
        assert_eq!(area["fill_per_px"], light["volume_fill"], "{area}");
        assert_eq!(area["samples_passed_per_px"], light["volume_samples_passed"], "{area}");
        let (covered, passed) = (
            area["samples_covered_per_px"].as_f64().expect("covered"),
            area["samples_passed_per_px"].as_f64().expect("passed"),
        );
        assert!(covered > passed, "the probe kept the depth test: {area}");
    }

    let table = "profile --technique shadow-volume --scene lights --size 64x48 --samples 1 --caster-fill 2";
    let (out, _) = common::run_ok(&table.split(' ').collect::<Vec<_>>());
    assert!(out.contains("shadow volumes' area") && out.matches("samples covered/px").count() == 3, "{out}");
    // After a move the probe would draw the scene as loaded, not as moved: it says so.
    let moved = "profile --technique shadow-volume --scene lights --size 64x48 --samples 1 --move-model torus";
    let (moved_out, _) = common::run_ok(&moved.split(' ').collect::<Vec<_>>());
    assert!(moved_out.contains("shadow volumes' area: not measured with --move-model"), "{moved_out}");
    assert!(!moved_out.contains("samples covered/px"), "{moved_out}");
    let section = out.split("casters spending most of the volume fill").nth(1).expect("the caster table");
    assert_eq!(section.lines().filter(|l| l.contains("silhouette") || l.contains("two-sided")).count(), 2, "{out}");
    let refused = common::run_err(&["profile", "--technique", "shadow-map", "--size", "32x32", "--caster-fill"]);
    assert!(refused.contains("--caster-fill") && refused.contains("shadow-map"), "{refused}");
    let refused = common::run_err(&["profile", "--size", "32x32", "--caster-fill", "0"]);
    assert!(refused.contains("--caster-fill"), "{refused}");
}
