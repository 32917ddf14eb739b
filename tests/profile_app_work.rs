//! `nostencil profile-app` on a headless program of our own that only computes and copies
//! (tests/common/work_program.rs, run as this binary's ignored test `profile_app_work::work_program`): with
//! `--frame-on submit` each of its submissions is a frame, and a budget recorded at one size of
//! its work catches a compute regression (more workgroups, more invocations) by the row's name.
//! Validation with synchronisation checks runs below the layer in the program, which fails on
//! any message.

use crate::common;

use std::path::Path;
use std::process::Output;

use common::work_program::{expected_rows, WorkOptions, LOCAL};
use nostencil_fillrate_report::report::FillrateReport;

const SUBMISSIONS: u32 = 3;

fn options(groups: u32) -> WorkOptions {
    WorkOptions { groups, submissions: SUBMISSIONS, boundary_every: 0 }
}

/// The program itself: `WORK_GROUPS` sets the size of its big dispatches.
#[test]
#[ignore = "a program for the other tests of this file, run by them through profile-app"]
fn work_program() {
    let groups = std::env::var("WORK_GROUPS").ok().and_then(|g| g.parse().ok()).unwrap_or(2);
    // SAFETY: the program's own plain Vulkan use.
    unsafe { common::work_program::run(c"work", options(groups)) };
    common::raw_vulkan::assert_no_messages();
}

/// `profile-app --frame-on submit --format json --out DIR/NAME.json EXTRA -- <this binary's
/// work_program>` with `groups`, validation (synchronisation checks on) below the layer.
fn profile(dir: &Path, name: &str, extra: &[&str], groups: u32) -> Output {
    let settings = common::raw_vulkan::synchronisation_settings(dir);
    let out = dir.join(format!("{name}.json"));
    let me = std::env::current_exe().expect("this test binary");
    let (out, me) = (out.to_string_lossy().into_owned(), me.to_string_lossy().into_owned());
    let args = [
        &["profile-app", "--frame-on", "submit", "--format", "json", "--out", out.as_str()][..],
        extra,
        &["--", me.as_str(), "--exact", "profile_app_work::work_program", "--ignored", "--test-threads=1"],
    ]
    .concat();
    common::nostencil_command(&args)
        .env("WORK_GROUPS", groups.to_string())
        .env("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation")
        .env("VK_LAYER_SETTINGS_PATH", &settings)
        .output()
        .expect("profile-app runs")
}

#[test]
fn frame_on_submit_gives_a_frame_per_submission_and_a_budget_catches_a_compute_regression() {
    let dir = common::scratch_dir("profile_app_work");
    let budget = dir.join("budget.json");
    let budget_arg = budget.to_string_lossy().into_owned();

    let (chart, trace) = (dir.join("chart.svg"), dir.join("trace.json"));
    let (chart_arg, trace_arg) = (chart.to_string_lossy().into_owned(), trace.to_string_lossy().into_owned());
    let extra = ["--record-budget", budget_arg.as_str(), "--chart", chart_arg.as_str(), "--trace", trace_arg.as_str()];
    let output = profile(&dir, "record", &extra, 2);
    let (_, stderr) = common::assert_success("record a budget", &output);
    assert!(stderr.contains("dispatch groups and transfers"), "{stderr}");
    let text = std::fs::read_to_string(dir.join("record.json")).expect("report");
    let report = FillrateReport::from_json(&text).expect("report");
    assert_eq!(report.frames_measured, SUBMISSIONS as u64, "one frame per submission");
    let rows = expected_rows(options(2));
    assert!(report.frames.iter().all(|f| f.work.len() == rows.len()));
    // A bar per work row in the chart, a GPU slice per work row of every frame in the trace.
    let svg = std::fs::read_to_string(&chart).expect("chart");
    assert!(svg.contains("compute #2") && svg.contains("vkCmdDispatchIndirect"), "{svg}");
    let trace: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&trace).expect("trace")).expect("JSON");
    let slices = trace["traceEvents"].as_array().expect("events").iter().filter(|e| e["ph"] == "X");
    let compute = slices.filter(|e| e["cat"] == "compute").count();
    let groups = rows.iter().filter(|r| r.0 == "compute").count();
    assert_eq!(compute, groups * SUBMISSIONS as usize);

    // --frames counts these frames too: two of the three submissions are measured.
    let output = profile(&dir, "two", &["--frames", "2"], 2);
    common::assert_success("--frames 2 --frame-on submit", &output);
    let text = std::fs::read_to_string(dir.join("two.json")).expect("report");
    assert_eq!(FillrateReport::from_json(&text).expect("report").frames_measured, 2);

    let output = profile(&dir, "same", &["--budget", budget_arg.as_str()], 2);
    let (_, stderr) = common::assert_success("the same work within its budget", &output);
    assert!(stderr.contains("within budget"), "{stderr}");

    // Three workgroups along x instead of two: the labelled group does 4 x 3 workgroups.
    let output = profile(&dir, "more", &["--budget", budget_arg.as_str()], 3);
    let stderr = common::assert_failure("more compute than the budget", &output);
    let (before, after) = (4 * 2 * LOCAL, 4 * 3 * LOCAL);
    let line = format!("pass 'compute #2 'add'': compute invocations {after} > budget {before}");
    assert!(stderr.contains(&line), "{stderr}");
    assert!(stderr.contains("pass 'compute #2 'add'': workgroups 12 > budget 8"), "{stderr}");
    assert!(stderr.contains("over the budget"), "{stderr}");
}
