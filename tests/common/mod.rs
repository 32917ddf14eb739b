//! Shared by the tests of both builds (the integration suite, `tests/suite.rs`, and the tests
//! compiled into the library, `tests/inside/`): a GPU with the validation layer on, the check
//! that it reported nothing, and the `nostencil` program run as a user runs it.

#![allow(dead_code)]

use std::sync::Arc;

use nostencil::{Gpu, GpuOptions};

pub mod draw_program;
pub mod gl_program;
pub mod raw_vulkan;
pub mod work_program;
pub mod x_server;

/// A GPU with the Khronos validation layer recording every message (every check), on the
/// device `NOSTENCIL_DEVICE` names or the one chosen automatically.
pub fn gpu() -> Arc<Gpu> {
    let options = GpuOptions { validation: Some(nostencil::ValidationChecks::ALL), ..GpuOptions::default() };
    match Gpu::new(&options) {
        Ok(gpu) => gpu,
        Err(e) => panic!("tests need a Vulkan device with the validation layer (run tools/setup-debian.sh): {e}"),
    }
}

/// The technique of the registry called `name`; a name that is not one fails the test.
pub fn technique(name: &str) -> nostencil::Technique {
    nostencil::technique(name).unwrap_or_else(|e| panic!("{e}"))
}

/// Fails the test on any validation message.
pub fn assert_no_validation_messages(gpu: &Gpu) {
    assert!(gpu.validation_enabled(), "validation layer is not on");
    let messages = gpu.validation_messages();
    assert!(messages.is_empty(), "{} validation message(s):\n{}", messages.len(), messages.join("\n"));
}

/// Whether a test that checks lavapipe's own figures (its fragment-count rule, its measured
/// counts) applies to `gpu`. On lavapipe, the device `cargo test` uses, it does. On a device a
/// user chose with `NOSTENCIL_DEVICE` it cannot, and says so on stderr (`--nocapture` shows
/// it). Any other device fails the test, naming it: such a test never passes without checking.
pub fn lavapipe_figures_apply(gpu: &Gpu, figures: &str) -> bool {
    let name = gpu.device_name();
    if name.contains("llvmpipe") {
        return true;
    }
    match std::env::var("NOSTENCIL_DEVICE") {
        Ok(chosen) => {
            eprintln!("SKIPPED: {figures} are lavapipe's; NOSTENCIL_DEVICE={chosen} chose '{name}'");
            false
        }
        Err(_) => {
            panic!("{figures} are lavapipe's, but the test device is '{name}' (set NOSTENCIL_DEVICE to choose it)")
        }
    }
}

/// Runs `body` in a child process of this test binary that runs the one test `path` (its
/// `module::name`), so that `body` may set the process environment (the fill-rate layer tests
/// load the layer into every instance their process creates) without reaching the tests that
/// run beside it in this binary. In that child, runs `body`. The child must report the test
/// passed, so a `path` that names no test fails instead of passing empty.
pub fn in_own_process(path: &str, body: impl FnOnce()) {
    const CHILD: &str = "NOSTENCIL_TEST_IN_OWN_PROCESS";
    if std::env::var(CHILD).is_ok_and(|running| running == path) {
        body();
        return;
    }
    let me = std::env::current_exe().expect("this test binary");
    let output = std::process::Command::new(me)
        .args(["--exact", path, "--nocapture", "--test-threads=1"])
        .env(CHILD, path)
        .output()
        .expect("run the test in a process of its own");
    let (stdout, stderr) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    print!("{stdout}");
    eprint!("{stderr}");
    assert!(
        output.status.success() && stdout.contains("test result: ok. 1 passed"),
        "{path} in a process of its own did not pass ({})",
        output.status
    );
}

/// `target/<profile>/`, where cargo puts the programs, found from this test binary
/// (`target/<profile>/deps/<test>`): cargo tells only the integration tests where they are.
fn target_profile_dir() -> std::path::PathBuf {
    let me = std::env::current_exe().expect("this test binary");
    let deps = me.parent().expect("the test binary's folder");
    deps.parent().expect("target/<profile>").to_path_buf()
}

/// `target/tmp/`, the folder under which tests write files.
pub fn scratch_root() -> std::path::PathBuf {
    match option_env!("CARGO_TARGET_TMPDIR") {
        Some(tmp) => std::path::PathBuf::from(tmp),
        None => target_profile_dir().parent().expect("target/").join("tmp"),
    }
}

/// Folder for files a test writes (under the target dir, removed and recreated per test name).
pub fn scratch_dir(test: &str) -> std::path::PathBuf {
    let dir = scratch_root().join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}

/// The real glTF files in the repository (`tests/assets`, origins and licences in its
/// `SOURCES.md`). A missing folder fails the tests by name instead of skipping them.
pub fn test_assets() -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/assets");
    assert!(dir.is_dir(), "{} not found: the tests need the glTF test assets", dir.display());
    dir
}

/// One file of the test assets; fails the test when it is missing.
pub fn test_asset(name: &str) -> std::path::PathBuf {
    let path = test_assets().join(name);
    assert!(path.is_file(), "{} not found", path.display());
    path
}

/// The `nostencil` program of this build. `cargo test` builds it for the integration suite
/// (which needs it) before any test runs; `cargo test --lib` alone does not, and then the
/// tests that run it fail here by name.
pub fn program() -> std::path::PathBuf {
    if let Some(path) = option_env!("CARGO_BIN_EXE_nostencil") {
        return path.into();
    }
    let path = target_profile_dir().join("nostencil");
    assert!(
        path.is_file(),
        "{} is not built: run `cargo test` (it builds the program), not `cargo test --lib`",
        path.display()
    );
    path
}

/// `nostencil ARGS` as a command, for a test that sets its environment before running it.
pub fn nostencil_command(args: &[&str]) -> std::process::Command {
    let mut command = std::process::Command::new(program());
    command.args(args);
    command
}

/// Runs `nostencil ARGS` and returns its output, whatever its exit status.
pub fn nostencil(args: &[&str]) -> std::process::Output {
    nostencil_command(args).output().expect("run nostencil")
}

/// A run that had to succeed: fails the test, showing stderr, on a non-zero exit or a panic.
/// Returns (stdout, stderr).
pub fn assert_success(what: &str, output: &std::process::Output) -> (String, String) {
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(output.status.success(), "`{what}` failed ({}):\n{stderr}", output.status);
    assert!(!stderr.contains("panicked"), "`{what}` panicked:\n{stderr}");
    (stdout, stderr)
}

/// A run that had to fail: a non-zero exit status (not a signal) and no panic. Returns stderr,
/// for the caller to check the message.
pub fn assert_failure(what: &str, output: &std::process::Output) -> String {
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert!(!output.status.success(), "`{what}` succeeded but had to fail:\n{stderr}");
    assert!(output.status.code().is_some(), "`{what}` was killed ({}):\n{stderr}", output.status);
    assert!(!stderr.contains("panicked"), "`{what}` panicked:\n{stderr}");
    stderr
}

/// Runs `nostencil ARGS`, which must succeed; returns (stdout, stderr).
pub fn run_ok(args: &[&str]) -> (String, String) {
    assert_success(&format!("nostencil {}", args.join(" ")), &nostencil(args))
}

/// Runs `nostencil ARGS`, which must fail cleanly; returns stderr.
pub fn run_err(args: &[&str]) -> String {
    assert_failure(&format!("nostencil {}", args.join(" ")), &nostencil(args))
}

/// A PNG the binary wrote, as RGB.
pub fn read_png(path: &std::path::Path) -> image::RgbImage {
    match image::open(path) {
        Ok(image) => image.to_rgb8(),
        Err(e) => panic!("{}: {e}", path.display()),
    }
}
