//! Out-of-memory and device errors, simulated where lavapipe cannot be made to fail: the fault
//! hooks of src/gpu/faults.rs, each behind its `NOSTENCIL_FAULT_*` variable, make a
//! submit return VK_ERROR_DEVICE_LOST or VK_ERROR_OUT_OF_DEVICE_MEMORY, or the device's heaps
//! look small. Each ends in a one-line error that names what failed (for a frame, its
//! passes), never a panic, and no file is written.

use crate::common;

use nostencil::builtin_scene;
use nostencil::{render_scene, technique as by_name, RenderOptions};

/// `nostencil ARGS` with the environment variable `key` set to `value`.
fn nostencil_with(key: &str, value: &str, args: &[&str]) -> std::process::Output {
    common::nostencil_command(args).env(key, value).output().expect("run nostencil")
}

/// The pass names of `technique`'s frame of the default scene at 64x48 (a real render).
fn pass_names(technique: &str) -> Vec<String> {
    let gpu = common::gpu();
    let scene = builtin_scene("default").expect("default scene");
    let technique = by_name(technique).expect("technique");
    let options = RenderOptions { technique, width: 64, height: 48, ..RenderOptions::default() };
    let frame = render_scene(&gpu, &scene, &options).expect("render");
    common::assert_no_validation_messages(&gpu);
    frame.output.counters.passes.iter().map(|p| p.name.clone()).collect()
}

#[test]
fn a_submit_failing_names_the_frames_passes_in_one_line_and_writes_nothing() {
    let dir = common::scratch_dir("gpu-faults-submit");
    let passes = pass_names("shadow-volume");
    assert!(passes.len() >= 3, "{passes:?}");
    for (fault, says) in
        [("frame:device-lost", "ERROR_DEVICE_LOST"), ("frame:out-of-device-memory", "ERROR_OUT_OF_DEVICE_MEMORY")]
    {
        let out = dir.join("frame.png");
        let args = ["render", "--validation", "--technique", "shadow-volume", "--size", "64x48", "--samples", "1"];
        let output =
            nostencil_with("NOSTENCIL_FAULT_SUBMIT", fault, &[&args[..], &["--out", out.to_str().unwrap()]].concat());
        let err = common::assert_failure(fault, &output);
        assert_eq!(err.trim_end().lines().count(), 1, "{fault}: not one line:\n{err}");
        assert!(err.contains("vkQueueSubmit failed") && err.contains(says), "{fault}:\n{err}");
        let listed = format!("the frame's passes: {}", passes.join(", "));
        assert!(err.contains(&listed), "{fault}: the passes are not named ({listed}):\n{err}");
        assert!(!out.exists(), "{fault}: {} was written", out.display());
    }
    // The same command without the fault renders (the injection is what failed it).
    let out = dir.join("frame.png");
    let args = ["render", "--validation", "--technique", "shadow-volume", "--size", "64x48", "--samples", "1"];
    common::run_ok(&[&args[..], &["--out", out.to_str().unwrap()]].concat());
    assert!(out.exists());
}

#[test]
fn a_frame_larger_than_the_heap_is_refused_before_anything_is_written() {
    let dir = common::scratch_dir("gpu-faults-heap");
    let out = dir.join("big.png");
    // 4096x4096 at 4x: colour and read-back 4 + 4, multisampled colour 16, depth 4 x 4 bytes a
    // pixel = 640 MiB, more than a 256 MiB heap.
    let args = ["render", "--size", "4096x4096", "--samples", "4", "--out", out.to_str().unwrap()];
    let err = common::assert_failure("4096x4096 4x", &nostencil_with("NOSTENCIL_FAULT_HEAP_MIB", "256", &args));
    assert_eq!(err.trim_end().lines().count(), 1, "not one line:\n{err}");
    assert!(err.contains("a 4096x4096 frame at 4x MSAA"), "{err}");
    assert!(err.contains("needs 640.0 MiB") && err.contains("(256.0 MiB)"), "{err}");
    assert!(err.contains("--size") && err.contains("--samples"), "says what to lower:\n{err}");
    // Refused up front: the message is the heap check's, made before any target is allocated.
    assert!(!out.exists(), "{} was written", out.display());

    // The check against the real heap: what it holds passes, one byte more is refused.
    let gpu = common::gpu();
    let heap = nostencil::gpu::memory::largest_device_heap(&gpu);
    assert!(heap > 0);
    assert!(nostencil::gpu::memory::check_fits_in_heap(&gpu, "test", heap, "").is_ok());
    let refused = nostencil::gpu::memory::check_fits_in_heap(&gpu, "test", heap + 1, "");
    assert!(refused.is_err_and(|e| e.to_string().contains("test needs")));
}
