//! `nostencil profile-app`: programs run under the fill-rate layer (VK_LAYER_NOSTENCIL_fillrate)
//! on lavapipe. A real application nobody here wrote (vkcube, on Xvfb); the differential against
//! `nostencil profile`'s own per-pass queries, summed per render pass instance, exact; images
//! byte-identical with and without the layer; a budget recorded from one run and overrun by a
//! larger window, named by render pass; the Khronos validation layer below the layer (with
//! synchronisation validation) reporting nothing, while it does report an application's error;
//! and an application with queries of its own (`nostencil profile`) unchanged by the layer.
//!
//! Needs vkcube (vulkan-tools) and Xvfb (tools/setup-debian.sh installs both): without them the
//! tests fail saying so rather than skip.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::x_server::{start_x_server, XServer};
use nostencil_fillrate_report::report::{FillrateReport, RenderPassRow};

/// vkcube's window (and so its swapchain) when no --width/--height is given.
const VKCUBE_SIZE: (u32, u32) = (500, 500);

/// Runs `nostencil ARGS` with `env` (on `x`'s display if given), stdout and stderr into files
/// (a pipe could fill and stall the child), at most three minutes. Returns (output, stdout).
fn run_nostencil(dir: &Path, name: &str, args: &[&str], env: &[(&str, &str)], x: Option<&XServer>) -> Output {
    let (out_path, err_path) = (dir.join(format!("{name}.stdout")), dir.join(format!("{name}.stderr")));
    let file = |p: &PathBuf| std::fs::File::create(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let mut command = Command::new(env!("CARGO_BIN_EXE_nostencil"));
    command.args(args).stdin(Stdio::null());
    command.stdout(file(&out_path)).stderr(file(&err_path));
    // The child's loader must see only what the test sets: no layers from the caller's shell.
    command.env_remove("VK_INSTANCE_LAYERS").env_remove("VK_LAYER_PATH").env_remove("VK_ADD_LAYER_PATH");
    if let Some(x) = x {
        command.env("DISPLAY", &x.display).env_remove("WAYLAND_DISPLAY");
    }
    for (key, value) in env {
        command.env(key, value);
    }
    let mut child = command.spawn().expect("run nostencil");
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("poll nostencil") {
            break status;
        }
        if start.elapsed() > Duration::from_secs(180) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("`nostencil {}` did not finish in 3 minutes", args.join(" "));
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let read = |p: &PathBuf| std::fs::read(p).unwrap_or_default();
    Output { status, stdout: read(&out_path), stderr: read(&err_path) }
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

fn read_report(path: &Path) -> FillrateReport {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    FillrateReport::from_json(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `nostencil profile-app --format json --out DIR/NAME.json EXTRA -- PROGRAM...`, which must
/// succeed; returns the layer's report and the run's output.
fn profile_app(
    dir: &Path,
    name: &str,
    extra: &[&str],
    program: &[&str],
    env: &[(&str, &str)],
    x: Option<&XServer>,
) -> (FillrateReport, Output) {
    let result = dir.join(format!("{name}.json"));
    let result_arg = result.to_string_lossy().into_owned();
    let args = [&["profile-app", "--format", "json", "--out", result_arg.as_str()], extra, &["--"], program].concat();
    let output = run_nostencil(dir, name, &args, env, x);
    common::assert_success(&format!("nostencil {}", args.join(" ")), &output);
    (read_report(&result), output)
}

/// The counters of a measured row; fails naming the row when it was not measured.
fn measured(row: &RenderPassRow) -> &nostencil_fillrate_report::report::Counters {
    row.counters.as_ref().unwrap_or_else(|| panic!("render pass {} not measured: {:?}", row.index, row.not_measured))
}

fn vkcube_args(frames: u32, size: Option<(u32, u32)>) -> Vec<String> {
    let mut args = vec!["vkcube".to_owned(), "--c".into(), frames.to_string()];
    if let Some((w, h)) = size {
        args.extend(["--width".into(), w.to_string(), "--height".into(), h.to_string()]);
    }
    args
}

#[test]
fn vkcube_has_one_render_pass_per_frame_at_its_window_size() {
    let x = start_x_server();
    let dir = common::scratch_dir("profile_app_vkcube");
    let program = vkcube_args(8, None);
    let program: Vec<&str> = program.iter().map(String::as_str).collect();
    let chart = dir.join("vkcube.svg");
    let chart_arg = chart.to_string_lossy().into_owned();
    let (report, _) = profile_app(&dir, "vkcube", &["--frames", "5", "--chart", &chart_arg], &program, &[], Some(&x));
    let svg = std::fs::read_to_string(&chart).expect("chart written");
    assert!(svg.starts_with("<svg") && svg.contains("render pass #0 500x500"), "{svg}");
    assert_eq!(report.frames_measured, 5, "{report:#?}");
    assert_eq!(report.frames.len(), 5);
    assert!(report.counters.pipeline_statistics && report.counters.occlusion_precise, "{:?}", report.counters);
    let pixels = (VKCUBE_SIZE.0 * VKCUBE_SIZE.1) as u64;
    for frame in &report.frames {
        assert_eq!(frame.render_passes.len(), 1, "frame {}: {:#?}", frame.index, frame.render_passes);
        let pass = &frame.render_passes[0];
        let area = &pass.render_area;
        assert_eq!((area.x, area.y, area.width, area.height), (0, 0, VKCUBE_SIZE.0, VKCUBE_SIZE.1));
        let roles: Vec<&str> = pass.attachments.iter().map(|a| a.role.as_str()).collect();
        assert_eq!(roles, ["colour", "depth"], "{:?}", pass.attachments);
        let counters = measured(pass);
        // One cube: 12 triangles in one draw; it covers part of the window, once.
        assert_eq!(counters.draws, 1);
        assert!(counters.samples_passed > 0 && counters.samples_passed < pixels, "{counters:?}");
        let per_pixel = counters.fragments_per_pixel.expect("fragments per pixel");
        assert!((0.1..4.0).contains(&per_pixel), "fragments per pixel {per_pixel}");
        assert!((counters.overdraw - counters.samples_passed as f64 / pixels as f64).abs() < 1e-9);
        // The colour image is presented (stored); the depth is cleared and dropped.
        let stored: u64 = pass.attachments.iter().map(|a| a.bytes_stored).sum();
        assert!(stored >= pixels * 4, "{:?}", pass.attachments);
    }
    eprintln!(
        "vkcube {}x{}: samples passed per frame {:?}, fragments {:?}",
        VKCUBE_SIZE.0,
        VKCUBE_SIZE.1,
        report.frames.iter().map(|f| measured(&f.render_passes[0]).samples_passed).collect::<Vec<_>>(),
        report.frames.iter().map(|f| measured(&f.render_passes[0]).fragment_invocations).collect::<Vec<_>>()
    );
}

#[test]
fn a_budget_recorded_from_vkcube_catches_a_larger_window_by_render_pass() {
    let x = start_x_server();
    let dir = common::scratch_dir("profile_app_budget");
    let budget = dir.join("budget.json");
    let budget_arg = budget.to_string_lossy().into_owned();
    let small = vkcube_args(4, Some((200, 200)));
    let small: Vec<&str> = small.iter().map(String::as_str).collect();
    profile_app(&dir, "record", &["--frames", "3", "--record-budget", &budget_arg], &small, &[], Some(&x));
    let recorded: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&budget).expect("budget written")).expect("budget JSON");
    assert_eq!(recorded["passes"][0]["name"], "render pass #0", "{recorded}");
    assert_eq!((recorded["width"].as_u64(), recorded["height"].as_u64()), (Some(200), Some(200)));

    let (_, output) = profile_app(&dir, "same", &["--frames", "3", "--budget", &budget_arg], &small, &[], Some(&x));
    assert!(text(&output.stderr).contains("within budget"), "{}", text(&output.stderr));

    let large = vkcube_args(4, Some((320, 320)));
    let args: Vec<&str> = ["profile-app", "--frames", "3", "--budget", &budget_arg, "--"]
        .into_iter()
        .chain(large.iter().map(String::as_str))
        .collect();
    let output = run_nostencil(&dir, "larger", &args, &[], Some(&x));
    let err = common::assert_failure("profile-app over budget", &output);
    let last = err.lines().last().unwrap_or_default();
    assert!(last.contains("over the budget") && last.contains("render pass #0 (320x320)"), "{err}");
    assert!(err.contains("over budget: pass 'render pass #0': samples passed"), "{err}");
}

/// `nostencil profile --format json` of the same frame: its passes' counters summed per render
/// pass instance (`render_pass_sums`), and the instances.
fn profile_sums(dir: &Path, name: &str, frame: &[&str]) -> serde_json::Value {
    let args = [&["profile", "--format", "json"], frame].concat();
    let output = run_nostencil(dir, name, &args, &[], None);
    let (stdout, _) = common::assert_success(&format!("nostencil {}", args.join(" ")), &output);
    serde_json::from_str(&stdout).expect("profile JSON")
}

/// The layer's rows `first..first + count` summed: (draws, samples passed, fragment invocations).
fn layer_sums(rows: &[RenderPassRow], first: usize, count: usize) -> (u64, u64, Option<u64>) {
    let rows = &rows[first..first + count];
    let draws = rows.iter().map(|r| measured(r).draws).sum();
    let samples = rows.iter().map(|r| measured(r).samples_passed).sum();
    let fragments = rows.iter().map(|r| measured(r).fragment_invocations).sum();
    (draws, samples, fragments)
}

/// `nostencil render --out PNG FRAME...`.
fn render_args<'a>(png: &'a str, frame: &[&'a str]) -> Vec<&'a str> {
    [&["render", "--out", png], frame].concat()
}

/// The layer measures `nostencil render --no-queries` (no query of the application's own: the
/// layer's queries alone count) and gets, per render pass instance, exactly the sums of the
/// per-pass queries `nostencil profile` records for the same frame; the PNG is the same with
/// and without the layer, with and without the application's queries.
#[test]
fn the_layer_measures_what_profile_sums_per_render_pass_and_changes_no_pixel() {
    let dir = common::scratch_dir("profile_app_differential");
    let frames: [&[&str]; 3] = [
        &["--technique", "shadow-volume", "--stencil", "reference", "--size", "128x128"],
        &["--technique", "planar", "--size", "128x96", "--samples", "1"],
        // Three prepasses (mask, blur x, blur y), each its own render pass, then the frame.
        &["--technique", "outline", "--outline-blur", "2", "--size", "96x96", "--samples", "1"],
    ];
    for (i, frame) in frames.iter().enumerate() {
        let png = |name: &str| dir.join(format!("{i}-{name}.png"));
        let (plain_png, unqueried_png, layered_png) = (png("plain"), png("unqueried"), png("layered"));
        let (plain_arg, unqueried_arg, layered_arg) =
            (plain_png.to_string_lossy(), unqueried_png.to_string_lossy(), layered_png.to_string_lossy());
        let plain = run_nostencil(&dir, &format!("{i}-plain"), &render_args(&plain_arg, frame), &[], None);
        common::assert_success("render without the layer", &plain);
        let unqueried_args = [&render_args(&unqueried_arg, frame)[..], &["--no-queries"]].concat();
        let unqueried = run_nostencil(&dir, &format!("{i}-unqueried"), &unqueried_args, &[], None);
        common::assert_success("render --no-queries without the layer", &unqueried);
        let program =
            [&[env!("CARGO_BIN_EXE_nostencil")], &render_args(&layered_arg, frame)[..], &["--no-queries"]].concat();
        let (report, _) = profile_app(&dir, &format!("{i}-layer"), &[], &program, &[], None);
        let bytes = |p: &PathBuf| std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        let plain_bytes = bytes(&plain_png);
        assert!(plain_bytes == bytes(&unqueried_png), "{frame:?}: --no-queries changed the PNG");
        assert!(plain_bytes == bytes(&layered_png), "{frame:?}: the layer changed the PNG");

        // `render` never presents: one frame, closed when its device is destroyed.
        assert_eq!(report.frames.len(), 1, "{frame:?}: {report:#?}");
        assert!(report.not_measured.is_empty(), "{frame:?}: {:?}", report.not_measured);
        let rows = &report.frames[0].render_passes;
        let profile = profile_sums(&dir, &format!("{i}-profile"), frame);
        let instances = profile["render_pass_instances"].as_array().expect("instances");
        assert_eq!(rows.len(), instances.len(), "{frame:?}: layer rows {rows:#?}\nprofile {instances:#?}");
        for (row, instance) in rows.iter().zip(instances) {
            let size = (instance["width"].as_u64(), instance["height"].as_u64());
            assert_eq!(size, (Some(row.render_area.width as u64), Some(row.render_area.height as u64)));
            assert_eq!(instance["samples"].as_u64(), Some(row.samples as u64), "{frame:?}");
            assert!(row.counters.as_ref().is_some_and(|c| c.gpu_ms.is_some()), "{frame:?}: {row:?}");
        }
        let sums = profile["render_pass_sums"].as_array().expect("sums");
        for sum in sums {
            let (first, count) =
                (sum["first"].as_u64().unwrap_or(0) as usize, sum["count"].as_u64().unwrap_or(0) as usize);
            let (draws, samples, fragments) = layer_sums(rows, first, count);
            let expected =
                (sum["draws"].as_u64(), sum["samples_passed"].as_u64(), sum["fragment_invocations"].as_u64());
            assert_eq!(
                (Some(draws), Some(samples), fragments),
                expected,
                "{frame:?}, instances {first}+{count}: {sum}"
            );
            assert!(samples > 0, "{frame:?}: nothing drawn");
            eprintln!(
                "{frame:?} render pass #{first}: draws {draws}, samples passed {samples}, fragments {fragments:?}"
            );
        }
    }
}

/// A vk_layer_settings.txt for the Khronos validation layer: core and synchronisation checks,
/// errors and warnings logged to stdout (no messenger is needed), and an INFO line saying which
/// checks are enabled, which proves the layer loaded with them.
fn validation_settings(dir: &Path) -> PathBuf {
    let path = dir.join("vk_layer_settings.txt");
    let settings = "khronos_validation.report_flags = info,warn,error\n\
                    khronos_validation.debug_action = VK_DBG_LAYER_ACTION_LOG_MSG\n\
                    khronos_validation.enables = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT\n";
    std::fs::write(&path, settings).expect("write settings");
    path
}

/// Validation errors and warnings (not the INFO status line) in a run's output.
fn validation_problems(output: &Output) -> Vec<String> {
    let all = format!("{}\n{}", text(&output.stdout), text(&output.stderr));
    let kinds = ["Validation Error", "Validation Warning", "Validation Performance Warning"];
    all.lines().filter(|l| kinds.iter().any(|k| l.contains(k))).map(str::to_owned).collect()
}

/// Fails unless the validation layer loaded with synchronisation checks and reported nothing.
fn assert_validation_silent(name: &str, output: &Output) {
    let stdout = text(&output.stdout);
    assert!(
        stdout.contains("Current Enables: VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION"),
        "{name}: the validation layer did not load with synchronisation checks:\n{stdout}\n{}",
        text(&output.stderr)
    );
    let problems = validation_problems(output);
    assert!(problems.is_empty(), "{name}: {} validation message(s):\n{}", problems.len(), problems.join("\n"));
}

#[test]
fn validation_below_the_layer_reports_nothing_but_would_report_an_application_error() {
    let x = start_x_server();
    let dir = common::scratch_dir("profile_app_validation");
    let settings = validation_settings(&dir);
    let settings = settings.to_string_lossy();
    // The fill-rate layer first (nearest the application), validation below it: the validation
    // layer sees every command the fill-rate layer adds.
    let layers = "VK_LAYER_NOSTENCIL_fillrate:VK_LAYER_KHRONOS_validation";
    let env = [("VK_INSTANCE_LAYERS", layers), ("VK_LAYER_SETTINGS_PATH", settings.as_ref())];
    let png = dir.join("frame.png");
    let png = png.to_string_lossy();
    let nostencil_render = [
        env!("CARGO_BIN_EXE_nostencil"),
        "render",
        "--technique",
        "shadow-volume",
        "--stencil",
        "reference",
        "--size",
        "96x96",
        "--out",
        png.as_ref(),
    ];
    let vkcube = vkcube_args(5, None);
    let vkcube: Vec<&str> = vkcube.iter().map(String::as_str).collect();
    for (name, program) in [("vkcube", &vkcube[..]), ("render", &nostencil_render[..])] {
        let (report, output) = profile_app(&dir, name, &[], program, &env, Some(&x));
        assert_validation_silent(name, &output);
        let measured_rows = report.frames.iter().flat_map(|f| &f.render_passes).filter(|r| r.counters.is_some());
        assert!(measured_rows.count() > 0, "{name}: nothing measured: {report:#?}");
    }
    // The loader's own account of the chain, top (application) down: the fill-rate layer, then
    // validation below it.
    let debug_env = [env[0], env[1], ("VK_LOADER_DEBUG", "layer")];
    let (_, output) = profile_app(&dir, "chain", &[], &nostencil_render, &debug_env, None);
    let log = format!("{}{}", text(&output.stdout), text(&output.stderr));
    let chain = log.find("vkCreateInstance layer callstack setup to:").map(|at| &log[at..]).expect("loader chain");
    let (ours, validation) = (chain.find("VK_LAYER_NOSTENCIL_fillrate"), chain.find("VK_LAYER_KHRONOS_validation"));
    assert!(matches!((ours, validation), (Some(a), Some(b)) if a < b), "layer order:\n{chain}");
    // The same setup does see an application's error (vkcube --force_errors makes one).
    let forced = [&vkcube[..], &["--force_errors"]].concat();
    let (_, output) = profile_app(&dir, "forced", &[], &forced, &env, Some(&x));
    assert!(!validation_problems(&output).is_empty(), "no message for a forced error:\n{}", text(&output.stdout));
}

/// `nostencil profile`'s per-pass counters, by pass: (name, draws, samples passed, fragments).
fn pass_counters(report: &serde_json::Value) -> Vec<(String, u64, u64, u64)> {
    let passes = report["passes"].as_array().cloned().unwrap_or_default();
    let field = |p: &serde_json::Value, k: &str| p[k].as_u64().unwrap_or(u64::MAX);
    passes
        .iter()
        .map(|p| {
            let name = p["name"].as_str().unwrap_or("?").to_owned();
            (name, field(p, "draws"), field(p, "samples_passed"), field(p, "fragment_invocations"))
        })
        .collect()
}

/// `nostencil profile FRAME --format json` under the layer: (the layer's report, the program's
/// own JSON), and the same without the layer.
fn profile_with_and_without_the_layer(
    dir: &Path,
    frame: &[&str],
) -> (FillrateReport, serde_json::Value, serde_json::Value) {
    let plain = profile_sums(dir, "plain", frame);
    let program = [&[env!("CARGO_BIN_EXE_nostencil"), "profile", "--format", "json"], frame].concat();
    let (report, output) = profile_app(dir, "layered", &[], &program, &[], None);
    let layered: serde_json::Value = serde_json::from_str(&text(&output.stdout)).expect("profile JSON under the layer");
    (report, layered, plain)
}

/// `nostencil profile` brackets its own passes with occlusion and statistics queries: inside the
/// frame's render pass (the layer's queries pause and the program's occlusion query fills the
/// gap; its statistics query is never read by the layer, so that pass has no statistics) and
/// around the shadow texture's render pass (open across its begin: the layer cannot measure
/// that one and says so). It runs unbroken, its draws and samples passed are the same with and
/// without the layer, and the layer's frame render pass has its sums.
#[test]
fn an_application_with_queries_of_its_own_runs_and_the_layer_names_what_it_skipped() {
    let dir = common::scratch_dir("profile_app_app_queries");
    let frame = ["--technique", "shadow-texture", "--size", "96x96", "--samples", "1"];
    let (report, layered, plain) = profile_with_and_without_the_layer(&dir, &frame);
    let without_fragments = |report: &serde_json::Value| -> Vec<(String, u64, u64)> {
        pass_counters(report).into_iter().map(|(name, draws, samples, _)| (name, draws, samples)).collect()
    };
    assert_eq!(without_fragments(&plain), without_fragments(&layered), "the layer changed the program's counters");
    assert!(pass_counters(&plain).len() >= 2);

    // Two frames' worth (profile draws one to warm up), each the shadow texture's render pass,
    // then the frame's; `profile` never presents, so they make one frame.
    let rows = &report.frames.last().expect("a frame").render_passes;
    let instances = plain["render_pass_instances"].as_array().expect("instances");
    assert_eq!(rows.len(), 2 * instances.len(), "{rows:#?}");
    let reason = |r: &RenderPassRow| r.not_measured.clone().unwrap_or_default();
    for frame in rows.chunks(instances.len()) {
        assert!(frame[0].counters.is_none() && reason(&frame[0]).contains("query"), "{:#?}", frame[0]);
        let sum = &plain["render_pass_sums"][1];
        assert_eq!(sum["first"], 1);
        let (draws, samples, fragments) = layer_sums(frame, 1, 1);
        let expected = (sum["draws"].as_u64(), sum["samples_passed"].as_u64());
        assert_eq!((Some(draws), Some(samples)), expected, "frame render pass");
        assert_eq!(fragments, None, "statistics of a pass holding the program's statistics query");
    }
    let count = |what: &str| report.not_measured.iter().filter(|n| n.what == what).map(|n| n.count).sum::<u64>();
    let across = report.not_measured.iter().filter(|n| n.what.contains("across")).map(|n| n.count).sum::<u64>();
    assert_eq!(across, 2, "{:?}", report.not_measured);
    assert_eq!(count(nostencil_fillrate::readback::APP_STATISTICS_GAP), 2, "{:?}", report.not_measured);
}

/// The program's own fragment counts, too, are the same under the layer. On lavapipe (Mesa
/// 22.3) a second read of a pipeline-statistics query returns 17x its fragment invocations
/// (`llvmpipe_get_query_result` sums the per-thread counts into the stored value and multiplies
/// it by 16 in place), so when the layer read the program's statistics query to fill its gap,
/// the program then read 17x its own count (21456 -> 364752 for this frame's scene pass). The
/// layer now never reads an application's statistics query.
#[test]
fn an_application_with_queries_of_its_own_keeps_its_fragment_counts() {
    let dir = common::scratch_dir("profile_app_app_fragments");
    let frame = ["--technique", "shadow-volume", "--size", "96x96", "--samples", "1"];
    let (_, layered, plain) = profile_with_and_without_the_layer(&dir, &frame);
    assert_eq!(pass_counters(&plain), pass_counters(&layered), "the layer changed the program's own counters");
}

/// Every way a run can go wrong ends with one line naming it, and a non-zero exit.
#[test]
fn a_missing_failing_or_silent_program_gets_a_one_line_error() {
    let dir = common::scratch_dir("profile_app_errors");
    let cases: [(&[&str], &str); 5] = [
        (&["profile-app"], "needs the program to run after `--`"),
        (&["profile-app", "--", "/nonexistent/program"], "cannot start '/nonexistent/program': not found"),
        (&["profile-app", "--", "false"], "'false' exited with status 1"),
        // Runs and exits 0 but creates no Vulkan device: no result to report.
        (&["profile-app", "--", "true"], "'true' exited normally but the layer wrote no result"),
        (&["profile-app", "--frames", "0", "--", "true"], "--frames 0 would measure nothing"),
    ];
    for (i, (args, expected)) in cases.iter().enumerate() {
        let output = run_nostencil(&dir, &format!("case{i}"), args, &[], None);
        let err = common::assert_failure(&args.join(" "), &output);
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!(lines.len(), 1, "{args:?}: {err}");
        assert!(lines[0].starts_with("nostencil: error:") && lines[0].contains(expected), "{args:?}: {err}");
    }
    // A budget of nostencil's own frame is not an application's.
    let own = dir.join("own-budget.json");
    let own_arg = own.to_string_lossy();
    let record = ["profile", "--size", "64x64", "--samples", "1", "--record-budget", own_arg.as_ref()];
    common::assert_success("record", &run_nostencil(&dir, "record", &record, &[], None));
    let (png, report) = (dir.join("frame.png"), dir.join("report.txt"));
    let (png_arg, report_arg) = (png.to_string_lossy(), report.to_string_lossy());
    let args = [
        "profile-app",
        "--budget",
        own_arg.as_ref(),
        "--out",
        report_arg.as_ref(),
        "--",
        env!("CARGO_BIN_EXE_nostencil"),
        "render",
        "--size",
        "64x64",
        "--out",
        png_arg.as_ref(),
    ];
    let err =
        common::assert_failure("profile-app with an own-frame budget", &run_nostencil(&dir, "own", &args, &[], None));
    assert!(err.contains("not an application"), "{err}");
    // A pipe (or a device such as /dev/null) as the output is refused before anything runs:
    // the atomic write would replace it with a plain file. A pipe of the test's own is used.
    let fifo = dir.join("pipe");
    let made = Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo {}", fifo.display());
    let fifo_arg = fifo.to_string_lossy();
    let output = run_nostencil(&dir, "pipe", &["profile-app", "--out", fifo_arg.as_ref(), "--", "true"], &[], None);
    let err = common::assert_failure("profile-app --out PIPE", &output);
    assert!(err.contains("not a regular file"), "{err}");
}

/// `--per-draw` on `nostencil render --technique shadow-volume`: every draw of every measured
/// render pass counted on its own, and the draws' sums are the pass's counters exactly, with the
/// validation layer below silent.
#[test]
fn per_draw_counts_sum_to_each_render_pass_exactly() {
    let dir = common::scratch_dir("profile_app_per_draw");
    let settings = validation_settings(&dir);
    let settings = settings.to_string_lossy();
    let env = [("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation"), ("VK_LAYER_SETTINGS_PATH", settings.as_ref())];
    let png = dir.join("frame.png");
    let png = png.to_string_lossy();
    let frame = ["--technique", "shadow-volume", "--stencil", "reference", "--size", "96x96", "--no-queries"];
    let program = [&[env!("CARGO_BIN_EXE_nostencil")][..], &render_args(&png, &frame)].concat();
    let (report, output) = profile_app(&dir, "per_draw", &["--per-draw"], &program, &env, None);
    let problems = validation_problems(&output);
    assert!(problems.is_empty(), "{} validation message(s):\n{}", problems.len(), problems.join("\n"));
    let rows: Vec<&RenderPassRow> = report.frames.iter().flat_map(|f| &f.render_passes).collect();
    let mut draws_seen = 0;
    for row in rows.iter().filter(|r| r.counters.is_some()) {
        let pass = measured(row);
        assert_eq!(row.per_draw.len() as u64, pass.draws, "pass {}: {:?}", row.index, row.per_draw);
        let samples: u64 = row.per_draw.iter().map(|d| d.samples_passed).sum();
        let fragments: Option<u64> = row.per_draw.iter().map(|d| d.fragment_invocations).sum();
        assert_eq!((samples, fragments), (pass.samples_passed, pass.fragment_invocations), "pass {}", row.index);
        assert!(row.per_draw.iter().all(|d| d.gpu_ms.is_some_and(|t| t >= 0.0)), "{:?}", row.per_draw);
        draws_seen += row.per_draw.len();
    }
    assert!(draws_seen > 5, "a shadow-volume frame has many draws: {report:#?}");
    assert!(rows.iter().any(|r| r.per_draw.iter().filter(|d| d.samples_passed > 0).count() > 1), "{report:#?}");
    // Without --per-draw there is no per-draw list.
    let (plain, _) = profile_app(&dir, "plain", &[], &program, &[], None);
    assert!(plain.frames.iter().flat_map(|f| &f.render_passes).all(|r| r.per_draw.is_empty()));
}

/// `profile-app --tiler-check` on programs that do it right: `nostencil render`, every
/// technique at 1 and 4 samples, gets no flag and writes the very PNG it writes without the
/// layer (the pattern fills only what the frame never reads: the dropped depth, DONT_CARE loads
/// that the frame overwrites whole); nor does `nostencil view`, but for the blit of its frame
/// into the swapchain image (a full frame of system-memory traffic on a tiler), and its
/// presented image (its screenshot) is the same with the check. (vkcube: the next test.)
#[test]
fn the_tiler_check_flags_nothing_and_changes_no_pixel_of_programs_that_do_it_right() {
    let dir = common::scratch_dir("profile_app_tiler_check");
    let mut poisoned = 0;
    for technique in nostencil::TECHNIQUES.iter().map(|t| t.name()) {
        for samples in ["1", "4"] {
            let name = format!("{technique}-{samples}");
            let png = |kind: &str| dir.join(format!("{name}-{kind}.png"));
            let (plain_png, checked_png) = (png("plain"), png("checked"));
            let (plain_arg, checked_arg) = (plain_png.to_string_lossy(), checked_png.to_string_lossy());
            let frame = ["--technique", technique, "--samples", samples, "--size", "64x64"];
            let plain = run_nostencil(&dir, &format!("{name}-plain"), &render_args(&plain_arg, &frame), &[], None);
            common::assert_success("render without the layer", &plain);
            let program = [&[env!("CARGO_BIN_EXE_nostencil")], &render_args(&checked_arg, &frame)[..]].concat();
            let (report, output) =
                profile_app(&dir, &format!("{name}-checked"), &["--tiler-check"], &program, &[], None);
            let check = report.tiler_check.as_ref().unwrap_or_else(|| panic!("{name}: no tiler check in the report"));
            assert!(check.flags.is_empty(), "{name}: {:#?}", check.flags);
            assert!(text(&output.stderr).contains("tiler check: no flag"), "{name}");
            let bytes = |p: &PathBuf| std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            assert!(bytes(&plain_png) == bytes(&checked_png), "{name}: the tiler check changed the PNG");
            poisoned += check.poisoned.len();
        }
    }
    assert!(poisoned > 0, "the frames drop their depth: something was poisoned");

    // A presenting program whose presented image can be compared: `nostencil view`'s screenshot
    // is a copy of the swapchain image it presents.
    let x = start_x_server();
    let shot = |kind: &str| dir.join(format!("view-{kind}.png"));
    let (plain_shot, checked_shot, copied_shot) = (shot("plain"), shot("checked"), shot("copied"));
    let view = |png: &PathBuf, present: &str| {
        let png = png.to_string_lossy().into_owned();
        ["view", "--frames", "3", "--size", "64x64", "--paused", "--present", present, "--screenshot"]
            .map(str::to_owned)
            .into_iter()
            .chain([png])
            .collect::<Vec<String>>()
    };
    let plain_args = view(&plain_shot, "direct");
    let plain_args: Vec<&str> = plain_args.iter().map(String::as_str).collect();
    common::assert_success("view without the layer", &run_nostencil(&dir, "view-plain", &plain_args, &[], Some(&x)));
    let under_check = |name: &str, args: &[String]| {
        let program: Vec<&str> =
            [env!("CARGO_BIN_EXE_nostencil")].into_iter().chain(args.iter().map(String::as_str)).collect();
        let result = dir.join(format!("{name}.json"));
        let result_arg = result.to_string_lossy().into_owned();
        let args =
            [&["profile-app", "--format", "json", "--out", result_arg.as_str(), "--tiler-check", "--"], &program[..]]
                .concat();
        (run_nostencil(&dir, name, &args, &[], Some(&x)), result)
    };

    // view draws into the swapchain image (its 4x frame resolved there in the render pass):
    // no copy into it, and no flag.
    let (output, report) = under_check("view-direct", &view(&checked_shot, "direct"));
    common::assert_success("view under --tiler-check", &output);
    let report = read_report(&report);
    let check = report.tiler_check.as_ref().expect("view's tiler check");
    assert!(check.flags.is_empty(), "view: {:#?}", check.flags);
    assert!(!report.frames.is_empty());
    for frame in &report.frames {
        let copies: Vec<_> = frame.work.iter().filter(|w| w.note.is_some()).collect();
        assert!(copies.is_empty(), "frame {}: a copy into the swapchain image: {copies:#?}", frame.index);
        assert!(frame.render_passes.iter().any(|p| p.counters.is_some()), "frame {}: no measured pass", frame.index);
    }

    // `--present copy` renders offscreen and blits the frame into the swapchain image: that
    // blit is a work row with the frame's bytes, and the check's one finding (exit 1).
    let (output, report) = under_check("view-copy", &view(&copied_shot, "copy"));
    let stderr = common::assert_failure("view --present copy under --tiler-check", &output);
    assert!(stderr.contains("tiler-check flag(s) for") && stderr.contains("full_frame_copy_to_swapchain"), "{stderr}");
    let report = read_report(&report);
    let check = report.tiler_check.as_ref().expect("view's tiler check");
    let kinds: Vec<&str> = check.flags.iter().map(|f| f.kind.as_str()).collect();
    assert!(
        !kinds.is_empty() && kinds.iter().all(|k| *k == "full_frame_copy_to_swapchain"),
        "view: {:#?}",
        check.flags
    );
    for frame in &report.frames {
        let blits: Vec<_> = frame.work.iter().filter(|w| w.api == "vkCmdBlitImage" && w.note.is_some()).collect();
        assert_eq!(blits.len(), 1, "frame {}: one blit into the swapchain image", frame.index);
        let c = blits[0].counters.expect("measured");
        assert_eq!((c.bytes_read, c.bytes_written), (64 * 64 * 4, 64 * 64 * 4), "frame {}", frame.index);
    }
    // The frame drawn into the swapchain image is the one copied in, to the byte.
    let bytes = |p: &PathBuf| std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    assert!(bytes(&plain_shot) == bytes(&checked_shot), "the tiler check changed view's presented image");
    assert!(bytes(&plain_shot) == bytes(&copied_shot), "view's direct and copied frames differ");
    let bytes = |p: &PathBuf| std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    assert!(bytes(&plain_shot) == bytes(&checked_shot), "the tiler check changed view's presented image");
}

/// `profile-app --capture FILE.png --capture-frame N -- vkcube --c 6`, the Khronos validation
/// layer (synchronisation checks on) below the fill-rate layer: the image vkcube presents at
/// the end of frame N, copied by the layer. Returns the PNG's bytes and the layer's report;
/// fails on any validation message.
fn vkcube_capture(dir: &Path, name: &str, frame: u32, extra: &[&str], x: &XServer) -> (Vec<u8>, FillrateReport) {
    let settings = validation_settings(dir);
    let settings = settings.to_string_lossy();
    let env = [("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation"), ("VK_LAYER_SETTINGS_PATH", settings.as_ref())];
    let png = dir.join(format!("{name}.png"));
    let png_arg = png.to_string_lossy().into_owned();
    let frame = frame.to_string();
    let args = [&["--capture", png_arg.as_str(), "--capture-frame", frame.as_str()], extra].concat();
    // vkcube turns its cube by a fixed angle each frame: frame N is the same image every run.
    let program = vkcube_args(6, Some((128, 128)));
    let program: Vec<&str> = program.iter().map(String::as_str).collect();
    let (report, output) = profile_app(dir, name, &args, &program, &env, Some(x));
    assert_validation_silent(name, &output);
    (std::fs::read(&png).unwrap_or_else(|e| panic!("{}: {e}", png.display())), report)
}

/// vkcube does it right for a tiler: `--tiler-check` flags nothing, and the image it presents
/// (the layer's capture of frame 4) is byte for byte the one it presents without the check,
/// which is the same in two runs without it; frame 2's is another (the cube turns).
#[test]
fn vkcube_gets_no_tiler_flag_and_presents_the_same_image_with_the_check() {
    let x = start_x_server();
    let dir = common::scratch_dir("profile_app_vkcube_capture");
    let (plain, _) = vkcube_capture(&dir, "plain", 4, &[], &x);
    let (again, _) = vkcube_capture(&dir, "again", 4, &[], &x);
    assert!(plain == again, "vkcube's frame 4 differs between two runs: no comparison can be made");
    let image = image::load_from_memory(&plain).expect("a PNG").to_rgb8();
    assert_eq!(image.dimensions(), (128, 128));
    let (corner, centre) = (image.get_pixel(2, 2), image.get_pixel(64, 64));
    assert_ne!(corner, centre, "the cube in the middle of the background");
    let (earlier, _) = vkcube_capture(&dir, "frame-2", 2, &[], &x);
    assert!(earlier != plain, "frame 2's image is frame 4's: the capture did not pick its frame");

    let (checked, report) = vkcube_capture(&dir, "checked", 4, &["--tiler-check"], &x);
    let check = report.tiler_check.expect("vkcube's tiler check");
    assert!(check.flags.is_empty(), "vkcube: {:#?}", check.flags);
    // Its depth is cleared and dropped each frame: poisoned after the pass, never read.
    assert!(!check.poisoned.is_empty() && check.poisoned.iter().all(|p| p.read_by.is_none()), "{:?}", check.poisoned);
    assert!(checked == plain, "the tiler check changed vkcube's presented image");

    // A frame the program never presents: no image, and an error that says so; with --frames,
    // refused before the program runs.
    let never = dir.join("never.png");
    let never_arg = never.to_string_lossy().into_owned();
    let vkcube = vkcube_args(6, Some((128, 128)));
    let vkcube: Vec<&str> = vkcube.iter().map(String::as_str).collect();
    for (frames, message) in [(None, "captured no image of frame 9"), (Some("9"), "is not among the 9 frames")] {
        let frames: Vec<&str> = frames.map(|n| vec!["--frames", n]).unwrap_or_default();
        let capture = ["profile-app", "--capture", &never_arg, "--capture-frame", "9"];
        let args = [&capture[..], &frames, &["--"], &vkcube].concat();
        let stderr = common::assert_failure(&args.join(" "), &run_nostencil(&dir, "never", &args, &[], Some(&x)));
        assert!(stderr.contains(message) && !never.exists(), "{stderr}");
    }
}

/// `profile-app --trace`: the layer's measured passes, then the frame's work rows, one GPU slice
/// each with the report's GPU time, laid end to end; the frame's counters (samples, bytes, a
/// transfer's counted) equal the report's.
#[test]
fn the_trace_of_an_applications_frames_has_the_reports_passes_and_counters() {
    let dir = common::scratch_dir("profile_app_trace");
    let (png, trace) = (dir.join("frame.png"), dir.join("trace.json"));
    let (png_arg, trace_arg) = (png.to_string_lossy().into_owned(), trace.to_string_lossy().into_owned());
    let frame = ["--technique", "outline", "--outline-blur", "2", "--size", "64x64", "--samples", "1"];
    // --no-queries: the layer's queries alone, every render pass measured.
    let program = [&[env!("CARGO_BIN_EXE_nostencil")], &render_args(&png_arg, &frame)[..], &["--no-queries"]].concat();
    let (report, _) = profile_app(&dir, "report", &["--trace", &trace_arg], &program, &[], None);
    let text = std::fs::read_to_string(&trace).expect("trace written");
    let trace: serde_json::Value = serde_json::from_str(&text).expect("the trace is JSON");
    let events = trace["traceEvents"].as_array().expect("traceEvents");
    let slices: Vec<&serde_json::Value> = events.iter().filter(|e| e["ph"] == "X").collect();
    let passes: Vec<f64> = report.frames[0].render_passes.iter().filter_map(|p| p.counters?.gpu_ms).collect();
    assert!(passes.len() >= 4, "three prepasses and the frame: {passes:?}");
    // Then the frame's work outside render passes (uploads, the read-back copy), also timed.
    let work = report.frames[0].work.iter().filter_map(|w| w.counters?.gpu_ms);
    let measured: Vec<f64> = passes.iter().copied().chain(work).collect();
    assert_eq!(slices.len(), measured.len());
    let mut end = 0.0;
    for (slice, ms) in slices.iter().zip(&measured) {
        let (ts, dur) = (slice["ts"].as_f64().expect("ts"), slice["dur"].as_f64().expect("dur"));
        assert!((dur - ms * 1e3).abs() < 1e-6 * dur.max(1.0), "{slice} against {ms} ms");
        assert!((ts - end).abs() < 1e-6 * ts.max(1.0), "laid end to end: {slice}");
        end = ts + dur;
    }
    let counters: Vec<_> = report.frames[0].render_passes.iter().filter_map(|p| p.counters).collect();
    let samples: u64 = counters.iter().map(|c| c.samples_passed).sum();
    let transfers: u64 =
        report.frames[0].work.iter().filter_map(|w| w.counters).map(|c| c.bandwidth().tiler_bytes).sum();
    let tiler: u64 = counters.iter().map(|c| c.tiler_bytes).sum::<u64>() + transfers;
    let counter = |name: &str, series: &str| {
        events.iter().find(|e| e["ph"] == "C" && e["name"] == name).map(|e| e["args"][series].clone())
    };
    assert_eq!(counter("samples", "samples passed"), Some(samples.into()));
    assert_eq!(counter("bytes", "tiler"), Some(tiler.into()));
}
