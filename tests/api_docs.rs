//! The API documentation builds without a warning: `cargo doc --no-deps --workspace` with
//! `RUSTDOCFLAGS=-D warnings`, as a reader's `cargo doc` would meet it. A broken intra-doc link
//! or a stray HTML tag fails here, not on the page. It builds into a target folder of its own
//! (`target/api-docs`), so that neither it nor a reader's `cargo doc` rebuilds the other's
//! pages, and no lock of the outer `cargo test` is waited on. On a fresh checkout it checks the
//! dependencies once (about a minute and a half on two busy cores); after that, seconds.

use std::path::Path;
use std::process::Command;

#[test]
fn the_api_documentation_builds_without_warnings() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cargo = option_env!("CARGO").unwrap_or("cargo");
    let output = Command::new(cargo)
        .args(["doc", "--no-deps", "--workspace", "--quiet"])
        .current_dir(root)
        .env("RUSTDOCFLAGS", "-D warnings")
        .env("CARGO_TARGET_DIR", root.join("target/api-docs"))
        .output()
        .unwrap_or_else(|e| panic!("{cargo} doc: {e}"));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "cargo doc with RUSTDOCFLAGS=-D warnings failed:\n{stderr}");
    assert!(!stderr.contains("warning"), "cargo doc warned:\n{stderr}");
}
