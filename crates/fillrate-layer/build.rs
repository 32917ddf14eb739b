//! Writes `target/<profile>/VkLayer_nostencil_fillrate.json` beside the
//! `libnostencil_fillrate.so` cargo links there: `VK_LAYER_PATH=target/debug` enables the layer.
//! OUT_DIR is `target/<profile>/build/nostencil-fillrate-layer-<hash>/out`, three folders below.

use std::path::PathBuf;

#[path = "../fillrate-report/src/manifest.rs"]
#[allow(dead_code)]
mod manifest;

fn main() {
    println!("cargo:rerun-if-changed=../fillrate-report/src/manifest.rs");
    let Some(out_dir) = std::env::var_os("OUT_DIR").map(PathBuf::from) else { return };
    let Some(profile_dir) = out_dir.ancestors().nth(3) else { return };
    let text = manifest::manifest_json(&format!("./{}", manifest::LIBRARY_FILE));
    let path = profile_dir.join(manifest::MANIFEST_FILE);
    if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
        if let Err(e) = std::fs::write(&path, text) {
            println!("cargo:warning=cannot write {}: {e}", path.display());
            std::process::exit(1);
        }
    }
}
