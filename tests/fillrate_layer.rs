//! `VK_LAYER_NOSTENCIL_fillrate` (src/layer/) on a real application, this crate's own
//! `nostencil render` run as a separate process under the loader: the result file is written
//! with one frame whose render passes are the ones `nostencil profile` lists, the counters are
//! those `profile` measures (samples passed exactly; no statistics for a pass holding the
//! program's own statistics query, which the layer never reads), the PNG is byte-identical
//! with and without the layer, and validation above and below the layer stays silent.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{assert_success, nostencil_command, scratch_dir};
use nostencil_fillrate_report::manifest::{manifest_json, newest_library, LAYER_NAME, LIBRARY_FILE, MANIFEST_FILE};
use nostencil_fillrate_report::report::{FillrateReport, FILLRATE_SCHEMA};

/// A folder with a manifest for the freshest layer library cargo built beside the binary
/// (`cargo test` rebuilds it in deps/ only); build.rs's own manifest must exist too.
fn layer_dir() -> PathBuf {
    let bin_dir = Path::new(env!("CARGO_BIN_EXE_nostencil")).parent().expect("binary folder");
    assert!(bin_dir.join(MANIFEST_FILE).is_file(), "{} not written by build.rs", bin_dir.join(MANIFEST_FILE).display());
    let library = newest_library(bin_dir).unwrap_or_else(|| panic!("no {LIBRARY_FILE} under {}", bin_dir.display()));
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fillrate_layer_manifest");
    std::fs::create_dir_all(&dir).expect("manifest dir");
    let text = manifest_json(library.to_str().expect("utf-8 path"));
    // Written once per process run and identical each time: tests running in parallel agree.
    let path = dir.join(MANIFEST_FILE);
    if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
        let temp = dir.join(format!("{MANIFEST_FILE}.{}", std::process::id()));
        std::fs::write(&temp, &text).expect("write manifest");
        std::fs::rename(&temp, &path).expect("place manifest");
    }
    dir
}

/// `nostencil ARGS` under the layer (plus `extra_layers` below it), its result in `out` as
/// `format`; VK_ADD_LAYER_PATH keeps the system's layers (validation) findable.
fn run_under_layer(args: &[&str], out: Option<&Path>, env: &[(&str, &str)], extra_layers: &str) -> Output {
    let mut command = nostencil_command(args);
    command.env("VK_ADD_LAYER_PATH", layer_dir()).env("VK_INSTANCE_LAYERS", format!("{LAYER_NAME}{extra_layers}"));
    command.env_remove("NOSTENCIL_FILLRATE_OUT").env_remove("NOSTENCIL_FILLRATE_FORMAT");
    if let Some(out) = out {
        command.env("NOSTENCIL_FILLRATE_OUT", out);
    }
    for (name, value) in env {
        command.env(name, value);
    }
    command.output().expect("run nostencil")
}

fn read_report(path: &Path) -> FillrateReport {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    FillrateReport::from_json(&text).unwrap_or_else(|e| panic!("{e}:\n{text}"))
}

/// `nostencil profile ARGS --format json` as JSON.
fn profile(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["profile"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--format", "json"]);
    let (stdout, _) = assert_success("nostencil profile", &nostencil_command(&all).output().expect("run"));
    serde_json::from_str(&stdout).expect("profile JSON")
}

fn assert_no_validation_errors(what: &str, output: &Output) {
    let text = format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    for marker in ["Validation Error", "VUID-"] {
        assert!(!text.contains(marker), "{what}: validation reported:\n{text}");
    }
}

#[test]
fn render_under_the_layer_writes_profiles_counters_and_an_identical_png() {
    let dir = scratch_dir("fillrate_layer_render");
    let args = ["--size", "96x64", "--stencil", "reference", "--technique", "shadow-volume"];
    let plain = dir.join("plain.png");
    let layered = dir.join("layered.png");
    let out = dir.join("fillrate.json");
    let mut render = vec!["render"];
    render.extend_from_slice(&args);
    let output =
        nostencil_command(&[&render[..], &["--out", plain.to_str().expect("utf-8")]].concat()).output().expect("run");
    assert_success("nostencil render", &output);
    let output =
        run_under_layer(&[&render[..], &["--out", layered.to_str().expect("utf-8")]].concat(), Some(&out), &[], "");
    assert_success("nostencil render under the layer", &output);

    let a = std::fs::read(&plain).expect("plain PNG");
    let b = std::fs::read(&layered).expect("layered PNG");
    assert!(a == b, "the PNG differs with the layer ({} vs {} bytes)", a.len(), b.len());

    let report = read_report(&out);
    assert_eq!(report.schema, FILLRATE_SCHEMA);
    assert_eq!(report.application, "nostencil");
    assert!(report.counters.pipeline_statistics && report.counters.occlusion_precise && report.counters.timestamps);
    // No present: one frame, closed when the device was destroyed.
    assert_eq!((report.frames_measured, report.frames.len()), (1, 1));
    let not_measured: Vec<(&str, u64)> = report.not_measured.iter().map(|n| (n.what.as_str(), n.count)).collect();
    assert_eq!(not_measured, [(nostencil_fillrate::readback::APP_STATISTICS_GAP, 1)]);

    let profile = profile(&args);
    let render_passes = profile["render_passes"].as_array().expect("render_passes");
    let passes = report.frames[0].render_passes.clone();
    let profiled: Vec<(u64, u64)> = render_passes
        .iter()
        .flat_map(|rp| {
            let count = rp["count"].as_u64().unwrap_or(1) as usize;
            std::iter::repeat_n((rp["width"].as_u64().unwrap_or(0), rp["height"].as_u64().unwrap_or(0)), count)
        })
        .collect();
    let measured: Vec<(u64, u64)> =
        passes.iter().map(|p| (p.render_area.width as u64, p.render_area.height as u64)).collect();
    assert_eq!(measured, profiled, "render passes: layer vs profile");

    // One render pass holds every logical pass: its counters are their sums, exactly.
    let sum = |key: &str| {
        profile["passes"].as_array().expect("passes").iter().map(|p| p[key].as_u64().unwrap_or(0)).sum::<u64>()
    };
    let counters = passes[0].counters.expect("the frame's render pass is measured");
    assert!(counters.samples_passed > 0 && counters.draws > 0);
    assert_eq!(counters.samples_passed, sum("samples_passed"));
    // `render` counts its own passes' statistics inside the render pass: the layer leaves them.
    assert_eq!(counters.fragment_invocations, None);
    assert_eq!(counters.draws, sum("draws"));
    assert!(counters.gpu_ms.is_some_and(|ms| ms > 0.0));
    // The 4x frame stores only its resolve target: 96 x 64 x 4 bytes.
    assert_eq!((counters.bytes_loaded, counters.bytes_stored), (0, 96 * 64 * 4));
    assert_eq!(passes[0].samples, 4);
    let aggregate = &report.aggregate;
    assert_eq!(aggregate.len(), 1);
    assert_eq!((aggregate[0].frames, aggregate[0].min.samples_passed), (1, counters.samples_passed));
}

#[test]
fn an_application_query_across_a_prepass_is_named_and_the_frame_still_measured() {
    // shadow-texture's prepass query spans the prepass's render pass: the layer cannot begin its
    // own occlusion query there. The frame's render pass holds the frame's logical passes.
    let dir = scratch_dir("fillrate_layer_prepass");
    let out = dir.join("fillrate.json");
    let png = dir.join("frame.png");
    let args = ["--size", "96x64", "--samples", "1", "--technique", "shadow-texture"];
    let render = [&["render"], &args[..], &["--out", png.to_str().expect("utf-8")]].concat();
    assert_success("render under the layer", &run_under_layer(&render, Some(&out), &[], ""));
    let report = read_report(&out);
    let passes = &report.frames[0].render_passes;
    let profile = profile(&args);
    assert_eq!(passes.len(), profile["render_passes"].as_array().map_or(0, Vec::len));
    let reason = "application occlusion query active across the pass";
    assert_eq!(passes[0].not_measured.as_deref(), Some(reason));
    assert!(passes[0].counters.is_none());
    // The frame's render pass holds `render`'s own statistics queries: no statistics of the layer's.
    let statistics = nostencil_fillrate::readback::APP_STATISTICS_GAP;
    let not_measured: Vec<(&str, u64)> = report.not_measured.iter().map(|n| (n.what.as_str(), n.count)).collect();
    assert_eq!(not_measured, vec![(reason, 1), (statistics, 1)]);
    // The frame: every logical pass that drew into it (all but the prepass) summed.
    let frame_passes: Vec<&serde_json::Value> =
        profile["passes"].as_array().expect("passes").iter().filter(|p| p["name"] != "shadow texture").collect();
    let samples: u64 = frame_passes.iter().map(|p| p["samples_passed"].as_u64().unwrap_or(0)).sum();
    let counters = passes[1].counters.expect("the frame is measured");
    assert_eq!((passes[1].render_area.width, passes[1].render_area.height), (96, 64));
    assert_eq!(counters.samples_passed, samples);
}

#[test]
fn validation_above_and_below_the_layer_stays_silent() {
    let dir = scratch_dir("fillrate_layer_validation");
    for (case, extra, flag) in [("above", "", "--validation"), ("below", ":VK_LAYER_KHRONOS_validation", "")] {
        let out = dir.join(format!("{case}.json"));
        let png = dir.join(format!("{case}.png"));
        let mut args =
            vec!["render", "--size", "64x48", "--stencil", "reference", "--out", png.to_str().expect("utf-8")];
        if !flag.is_empty() {
            args.push(flag);
        }
        let output = run_under_layer(&args, Some(&out), &[], extra);
        assert_success(&format!("render, validation {case} the layer"), &output);
        assert_no_validation_errors(case, &output);
        let report = read_report(&out);
        let counters = report.frames[0].render_passes[0].counters.expect("measured");
        assert!(counters.samples_passed > 0, "{case}");
    }
}

#[test]
fn csv_and_table_outputs_and_no_output_named() {
    let dir = scratch_dir("fillrate_layer_formats");
    let png = dir.join("frame.png");
    let render = ["render", "--size", "64x48", "--samples", "1", "--out", png.to_str().expect("utf-8")];

    let csv = dir.join("fillrate.csv");
    assert_success("csv", &run_under_layer(&render, Some(&csv), &[("NOSTENCIL_FILLRATE_FORMAT", "csv")], ""));
    let text = std::fs::read_to_string(&csv).expect("csv written");
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].starts_with("frame,index,label,api,x,y,width,height,samples,attachments,draws,"));
    // nostencil labels its frame's render pass "frame" (VK_EXT_debug_utils), which the layer reports.
    assert!(lines[1].starts_with("0,0,frame,vkCmdBeginRenderPass,0,0,64,48,1,"), "{}", lines[1]);
    // The pass's aggregate lines leave the section column empty; its sections' name theirs. The
    // work columns after it are empty on a render pass's lines, its kind aside.
    let pass_tail = ",render_pass,,,,,";
    assert_eq!(lines.iter().filter(|l| l.starts_with("mean,0,") && l.ends_with(&format!(",{pass_tail}"))).count(), 1);
    let section = format!(",scene (ambient){pass_tail}");
    assert!(lines.iter().any(|l| l.starts_with("0,0,frame,") && l.ends_with(&section)), "{text}");
    assert!(lines.iter().any(|l| l.starts_with("mean,0,frame,") && l.ends_with(&section)), "{text}");

    let table = dir.join("fillrate.txt");
    assert_success("table", &run_under_layer(&render, Some(&table), &[("NOSTENCIL_FILLRATE_FORMAT", "table")], ""));
    let text = std::fs::read_to_string(&table).expect("table written");
    assert!(text.starts_with("nostencil | llvmpipe"), "{text}");
    assert!(text.contains("vkCmdBeginRenderPass") && text.contains("64x48x1"), "{text}");

    let output = run_under_layer(&render, None, &[], "");
    let (_, stderr) = assert_success("no output", &output);
    assert_eq!(stderr.matches("NOSTENCIL_FILLRATE_OUT is not set: measuring nothing").count(), 1, "{stderr}");
}

/// `nostencil passes --technique T`: the Markdown tables naming every pass of the technique.
fn passes_table(technique: &str) -> String {
    let (stdout, _) = assert_success(
        "nostencil passes",
        &nostencil_command(&["passes", "--technique", technique]).output().expect("run nostencil passes"),
    );
    stdout
}

#[test]
fn every_pass_label_inside_the_frame_is_a_section_whose_counters_sum_to_the_pass() {
    // nostencil labels each measured pass inside its one "frame" render pass (draw groups, no
    // subpasses): the layer reports each as a section under the frame's row, for every technique.
    let dir = scratch_dir("fillrate_layer_sections");
    for technique in nostencil::TECHNIQUES.iter().map(|t| t.name()) {
        let out = dir.join(format!("{technique}.json"));
        let png = dir.join(format!("{technique}.png"));
        let args = ["--size", "64x64", "--technique", technique];
        let render = [&["render"], &args[..], &["--out", png.to_str().expect("utf-8")]].concat();
        let output = run_under_layer(&render, Some(&out), &[], "");
        assert_success(&format!("render --technique {technique} under the layer"), &output);
        assert_no_validation_errors(technique, &output);
        let report = read_report(&out);
        let rows = &report.frames.last().expect("a frame").render_passes;
        let profile = profile(&args);
        let passes = profile["passes"].as_array().expect("passes");
        let name = |p: &serde_json::Value| p["name"].as_str().unwrap_or_default().to_owned();

        // Every pass `profile` measured is named in the report: as a section of the frame, or
        // (a prepass with a render pass of its own) as a render pass's label.
        let labels: Vec<String> = rows
            .iter()
            .flat_map(|r| r.label.iter().cloned().chain(r.sections.iter().filter_map(|s| s.label.clone())))
            .collect();
        let table = passes_table(technique);
        for pass in passes {
            assert!(labels.contains(&name(pass)), "{technique}: no row for '{}' in {labels:?}", name(pass));
            assert!(table.contains(&format!("| {} |", name(pass))), "{technique}: '{}' not in passes", name(pass));
        }
        // The frame's render pass (the last one labelled "frame": shadow-map renders its map
        // first): its sections are the passes drawn in it, in order, none unlabelled.
        let prepasses: Vec<&str> = rows.iter().filter_map(|r| r.label.as_deref()).filter(|l| *l != "frame").collect();
        let frame = rows.iter().rev().find(|r| r.label.as_deref() == Some("frame")).expect("the frame's render pass");
        let in_frame: Vec<String> = passes.iter().map(name).filter(|n| !prepasses.contains(&n.as_str())).collect();
        let sections: Vec<String> = frame.sections.iter().map(|s| s.label.clone().unwrap_or_default()).collect();
        assert_eq!(sections, in_frame, "{technique}: the frame's sections");

        for row in rows.iter().filter(|r| !r.sections.is_empty()) {
            let total = row.counters.expect("a pass with sections is measured");
            let counters: Vec<_> =
                row.sections.iter().map(|s| s.counters.expect("a section of a measured pass")).collect();
            assert_eq!(counters.iter().map(|c| c.draws).sum::<u64>(), total.draws, "{technique}: draws");
            assert_eq!(counters.iter().map(|c| c.samples_passed).sum::<u64>(), total.samples_passed, "{technique}");
            if let Some(fragments) = total.fragment_invocations {
                let sum: Option<u64> = counters.iter().map(|c| c.fragment_invocations).sum();
                assert_eq!(sum, Some(fragments), "{technique}: fragments");
            }
            assert!(counters.iter().all(|c| c.gpu_ms.is_some()), "{technique}: each section is timed");
        }

        // Differential: nostencil's own per-pass counters against the layer's sections. Draws
        // are counted independently (nostencil by its recorder, the layer by hooking vkCmdDraw*).
        // Samples passed: inside each pass nostencil's own precise occlusion query is active,
        // so the layer's section holds that query as a gap and adds its result: equal values
        // prove the attribution of queries to sections, not a second measurement. Fragment
        // invocations cannot be compared: nostencil's own statistics query is active in every
        // pass, and the layer never reads an application's statistics query (on llvmpipe a
        // second read changes the value), so the sections have none.
        for section in &frame.sections {
            let label = section.label.clone().unwrap_or_default();
            let pass = passes.iter().find(|p| name(p) == label).expect("a profiled pass");
            let counters = section.counters.expect("measured");
            assert_eq!(counters.draws, pass["draws"].as_u64().unwrap_or(u64::MAX), "{technique} '{label}': draws");
            let samples = pass["samples_passed"].as_u64().unwrap_or(u64::MAX);
            assert_eq!(counters.samples_passed, samples, "{technique} '{label}': samples passed");
            assert_eq!(counters.fragment_invocations, None, "{technique} '{label}'");
        }
        // With `render --no-queries` nostencil records no query of its own: the layer's own
        // segments measure each section, and every counter equals profile's for that pass
        // exactly, fragments, vertices and primitives included (lavapipe's counts are
        // deterministic). shadow-volume and outline also count each draw alone (per-draw rows
        // must sum to their section's counters).
        let per_draw = ["shadow-volume", "outline"].contains(&technique);
        let out = dir.join(format!("{technique}-no-queries.json"));
        let render = [&render[..], &["--no-queries"]].concat();
        let env: &[(&str, &str)] = if per_draw { &[("NOSTENCIL_FILLRATE_PER_DRAW", "1")] } else { &[] };
        let output = run_under_layer(&render, Some(&out), env, "");
        assert_success(&format!("render --no-queries --technique {technique} under the layer"), &output);
        assert_no_validation_errors(technique, &output);
        let report = read_report(&out);
        let rows = &report.frames.last().expect("a frame").render_passes;
        let frame = rows.iter().rev().find(|r| r.label.as_deref() == Some("frame")).expect("the frame's render pass");
        let total = frame.counters.expect("measured");
        let fragments: Option<u64> =
            frame.sections.iter().map(|s| s.counters.and_then(|c| c.fragment_invocations)).sum();
        assert_eq!(fragments, total.fragment_invocations, "{technique}: fragments sum");
        assert!(total.fragment_invocations.is_some(), "{technique}: no query of the program's, so statistics");
        for section in &frame.sections {
            let label = section.label.clone().unwrap_or_default();
            let pass = passes.iter().find(|p| name(p) == label).expect("a profiled pass");
            let c = section.counters.expect("measured");
            let ours = [
                Some(c.draws),
                Some(c.samples_passed),
                c.fragment_invocations,
                c.vertex_invocations,
                c.clipping_primitives,
            ];
            let keys = ["draws", "samples_passed", "fragment_invocations", "vertex_invocations", "clipping_primitives"];
            let theirs: Vec<Option<u64>> = keys.iter().map(|k| pass[k].as_u64()).collect();
            assert_eq!(ours.to_vec(), theirs, "{technique} '{label}': layer section vs profile ({keys:?})");
            if per_draw {
                assert_eq!(section.per_draw.len() as u64, c.draws, "{technique} '{label}': per-draw rows");
                let samples: u64 = section.per_draw.iter().map(|d| d.samples_passed).sum();
                let fragments: Option<u64> = section.per_draw.iter().map(|d| d.fragment_invocations).sum();
                assert_eq!((samples, fragments), (c.samples_passed, c.fragment_invocations), "{technique} '{label}'");
            }
        }
        if per_draw {
            assert_eq!(frame.per_draw.len() as u64, total.draws, "{technique}: the pass's per-draw rows");
        }

        // The aggregate keeps the sections.
        let aggregate = report.aggregate.iter().rev().find(|a| a.label.as_deref() == Some("frame")).expect("frame");
        let aggregated: Vec<String> = aggregate.sections.iter().map(|s| s.label.clone().unwrap_or_default()).collect();
        assert_eq!(aggregated, in_frame, "{technique}: aggregate sections");
    }
}
