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

/// The shared glTF folder beside the checkout (`../shared/assets`). The tests need it: a
/// missing folder fails them by name instead of skipping (a skipped test proves nothing).
pub fn shared_assets() -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/assets");
    assert!(dir.is_dir(), "{} not found: the tests need the shared glTF assets", dir.display());
    dir
}

/// One file of the shared assets; fails the test when it is missing.
pub fn shared_asset(name: &str) -> std::path::PathBuf {
    let path = shared_assets().join(name);
    assert!(path.is_file(), "{} not found", path.display());
    path
}
