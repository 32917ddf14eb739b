//! Shared by the integration tests: a GPU with the validation layer on, and the check that it
//! reported nothing.

#![allow(dead_code)]

use std::sync::Arc;

use nostencil::gpu::{Gpu, GpuOptions};

/// A GPU with the Khronos validation layer recording every message.
pub fn gpu() -> Arc<Gpu> {
    match Gpu::new(&GpuOptions::for_tests()) {
        Ok(gpu) => gpu,
        Err(e) => panic!("tests need a Vulkan device with the validation layer (run tools/setup-debian.sh): {e}"),
    }
}

/// Fails the test on any validation message.
pub fn assert_no_validation_messages(gpu: &Gpu) {
    assert!(gpu.validation_enabled(), "validation layer is not on");
    let messages = gpu.validation_messages();
    assert!(messages.is_empty(), "{} validation message(s):\n{}", messages.len(), messages.join("\n"));
}

/// Folder for files a test writes (under the target dir, removed and recreated per test name).
pub fn scratch_dir(test: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create scratch dir");
    dir
}
