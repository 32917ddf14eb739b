//! The command line as a user meets it: the README's commands work, and bad input gets a
//! one-line error and a non-zero exit, never a panic or a partial file.

mod common;

use std::path::Path;
use std::process::{Command, Output};

fn nostencil(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nostencil")).args(args).output().expect("run nostencil")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A failure a user caused: non-zero exit, one line on stderr naming the problem, no panic.
fn assert_clean_failure(output: &Output, mentions: &str) {
    let err = stderr(output);
    assert!(!output.status.success(), "expected failure, got success: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "expected one line, got:\n{err}");
    assert!(err.contains(mentions), "'{mentions}' not in: {err}");
}

#[test]
fn render_writes_a_png_of_the_requested_size() {
    let dir = common::scratch_dir("cli-render");
    let out = dir.join("frame.png");
    let output = nostencil(&["render", "--size", "192x128", "--out", out.to_str().unwrap(), "--validation"]);
    assert!(output.status.success(), "{}", stderr(&output));
    assert!(!stderr(&output).contains("vulkan validation"), "{}", stderr(&output));
    let image = image::open(&out).expect("a PNG").to_rgb8();
    assert_eq!(image.dimensions(), (192, 128));
}

#[test]
fn profile_json_is_readable_by_a_program() {
    let output = nostencil(&["profile", "--size", "128x96", "--format", "json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let report: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(report["schema"], "nostencil-profile/2");
    assert_eq!(report["width"], 128);
    let passes = report["passes"].as_array().expect("passes");
    let scene = passes.iter().find(|p| p["name"] == "scene").expect("scene pass");
    assert!(scene["samples_passed"].as_u64().unwrap() > 0);
    assert!(scene["fragment_invocations"].as_u64().unwrap() >= scene["samples_passed"].as_u64().unwrap());
    assert!(scene["gpu_ms"].as_f64().unwrap() > 0.0);
}

#[test]
fn profile_csv_and_table_list_the_passes() {
    let csv = nostencil(&["profile", "--size", "64x64", "--format", "csv"]);
    assert!(csv.status.success(), "{}", stderr(&csv));
    let text = String::from_utf8_lossy(&csv.stdout);
    assert!(text.starts_with("pass,draws,"));
    assert!(text.lines().any(|l| l.starts_with("scene,")));
    let table = nostencil(&["profile", "--size", "64x64"]);
    assert!(String::from_utf8_lossy(&table.stdout).contains("samples/px"));
}

#[test]
fn info_prints_device_profile_and_limits() {
    let output = nostencil(&["info", "--json"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let info: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    let limits = info["limits"].as_array().expect("limits");
    assert!(limits.iter().any(|l| l["name"] == "maxPushConstantsSize" && l["profile"] == "128"));
    assert!(limits.iter().all(|l| l["ok"] == true));
    assert_eq!(info["forbidden_features"].as_array().unwrap().len(), 6);
}

#[test]
fn unknown_option_is_a_one_line_error() {
    assert_clean_failure(&nostencil(&["render", "--out", "x.png", "--frobnicate"]), "--frobnicate");
}

#[test]
fn zero_and_oversized_sizes_are_refused() {
    assert_clean_failure(&nostencil(&["render", "--size", "0x256", "--out", "x.png"]), "at least 1");
    assert_clean_failure(&nostencil(&["profile", "--size", "5000x256"]), "4096");
    assert_clean_failure(&nostencil(&["profile", "--size", "big"]), "WIDTHxHEIGHT");
}

#[test]
fn unwritable_output_leaves_no_file() {
    let dir = common::scratch_dir("cli-unwritable");
    let out = dir.join("missing-folder").join("frame.png");
    assert_clean_failure(&nostencil(&["render", "--size", "32x32", "--out", out.to_str().unwrap()]), "frame.png");
    assert!(!out.exists());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "nothing may be left behind");
}

#[test]
fn unknown_scene_and_technique_are_named() {
    assert_clean_failure(&nostencil(&["profile", "--scene", "nowhere"]), "nowhere");
    assert_clean_failure(&nostencil(&["profile", "--technique", "magic"]), "magic");
}

#[test]
fn missing_vulkan_driver_is_a_clear_error() {
    let dir = common::scratch_dir("cli-no-device");
    let out = dir.join("frame.png");
    let output = Command::new(env!("CARGO_BIN_EXE_nostencil"))
        .args(["render", "--size", "32x32", "--out", out.to_str().unwrap()])
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .output()
        .expect("run");
    assert_clean_failure(&output, "Vulkan");
    assert!(!Path::new(&out).exists());
}

#[test]
fn what_the_gltf_loader_ignored_is_printed_as_a_warning() {
    let dir = common::scratch_dir("cli-gltf-warning");
    let out = dir.join("cornell.png");
    let scene = common::shared_asset("CornellBox.glb");
    let output =
        nostencil(&["render", "--scene", scene.to_str().unwrap(), "--size", "48x48", "--out", out.to_str().unwrap()]);
    let err = stderr(&output);
    assert!(output.status.success(), "{err}");
    assert!(
        err.lines().any(|l| l.starts_with("nostencil: warning:")
            && l.contains("CornellBox.glb")
            && l.contains("KHR_materials_emissive_strength")),
        "{err}"
    );
    assert!(out.is_file());
}
