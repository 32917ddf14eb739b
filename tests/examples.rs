//! The programs in `examples/` build with the crate (`cargo test` builds them) and run: one
//! glTF file from tests/assets to a PNG, and a missing file refused with its name; a one-file
//! sample (docs/porting.md) with its two options, validation silent, and anything else refused.

use crate::common;

use std::path::PathBuf;
use std::process::Command;

/// An example's binary, built by `cargo test` beside this test's own (target/debug/examples).
fn example(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    let debug = exe.parent().and_then(|deps| deps.parent()).expect("target/debug");
    let path = debug.join("examples").join(name);
    assert!(path.is_file(), "{} not built (cargo test builds examples)", path.display());
    path
}

#[test]
fn gltf_to_png_renders_a_real_file_and_names_a_missing_one() {
    let dir = common::scratch_dir("example_gltf_to_png");
    let out = dir.join("cornell.png");
    let input = common::test_asset("CornellBox.glb");
    let run = Command::new(example("gltf_to_png")).arg(&input).arg(&out).arg("shadow-volume").output().expect("run");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let image = image::open(&out).expect("a PNG").to_rgba8();
    assert_eq!(image.dimensions(), (320, 240));
    let first = *image.get_pixel(0, 0);
    assert!(image.pixels().any(|p| *p != first), "a uniform image");

    let missing = dir.join("no such file.glb");
    let run = Command::new(example("gltf_to_png")).arg(&missing).arg(dir.join("x.png")).output().expect("run");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no such file.glb"), "{stderr}");
    assert!(!dir.join("x.png").exists());
}

#[test]
fn pass_counters_prints_every_pass_of_the_frame() {
    let run = Command::new(example("pass_counters")).args(["shadow-volume", "box"]).output().expect("run");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    assert!(stdout.lines().any(|l| l.starts_with("scene ")), "{stdout}");
    assert!(stdout.lines().any(|l| l.starts_with("sun: volumes (alpha")), "{stdout}");
}

#[test]
fn a_sample_takes_its_two_options_writes_its_frame_and_refuses_anything_else() {
    let dir = common::scratch_dir("example_sample_options");
    let (alpha, stencil) = (dir.join("alpha.png"), dir.join("stencil.png"));
    // The program as a user runs it, with the Khronos validation layer turned on from outside
    // (the sample itself asks for none) and every message it has logged.
    let settings = dir.join("vk_layer_settings.txt");
    std::fs::write(
        &settings,
        "khronos_validation.report_flags = info,warn,error\n\
         khronos_validation.debug_action = VK_DBG_LAYER_ACTION_LOG_MSG\n\
         khronos_validation.enables = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT\n",
    )
    .expect("write the layer settings");
    for args in [vec!["--out".into(), alpha.clone()], vec!["--stencil".into(), "--out".into(), stencil.clone()]] {
        let run = Command::new(example("shadow_volumes"))
            .args(&args)
            .env("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation")
            .env("VK_LAYER_SETTINGS_PATH", &settings)
            .output()
            .expect("run");
        let all = format!("{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
        assert!(run.status.success(), "{all}");
        assert!(all.contains("Current Enables: VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION"), "no validation:\n{all}");
        let problems: Vec<&str> = all
            .lines()
            .filter(|l| {
                l.contains("Validation Error")
                    || l.contains("Validation Warning")
                    || l.contains("Validation Performance Warning")
            })
            .collect();
        assert!(problems.is_empty(), "{args:?}: {} validation message(s):\n{}", problems.len(), problems.join("\n"));
    }
    let (alpha, stencil) =
        (image::open(&alpha).expect("a PNG").to_rgba8(), image::open(&stencil).expect("a PNG").to_rgba8());
    assert_eq!(alpha.dimensions(), stencil.dimensions());
    assert!(alpha.pixels().zip(stencil.pixels()).all(|(a, s)| a.0[..3] == s.0[..3]), "alpha and --stencil differ");

    let run = Command::new(example("shadow_volumes")).args(["--size", "4"]).current_dir(&dir).output().expect("run");
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("unknown argument '--size'") && stderr.contains("usage: shadow_volumes"), "{stderr}");
    assert!(!dir.join("shadow_volumes.png").exists(), "a frame written despite a bad argument");
}
