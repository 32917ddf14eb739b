//! Tile traffic listed per render pass, counters summed per render pass instance, and the
//! bandwidth figures (JSON and CSV) against hand-computed ones, at one and four samples.

use super::*;

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
