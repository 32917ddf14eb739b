//! The loader's JSON manifest for `VK_LAYER_NOSTENCIL_fillrate` (Vulkan-Loader
//! docs/LoaderLayerInterface.md, "Layer Manifest File Format", file format 1.2.0).
//!
//! This file has no imports from the crate on purpose: the layer's build.rs includes it
//! (`#[path]`) to write `target/<profile>/VkLayer_nostencil_fillrate.json` next to
//! `libnostencil_fillrate.so`, and
//! `profile-app` calls [`manifest_json`] to write its own into a temp dir when that one is missing.

/// The layer's name, as `VK_INSTANCE_LAYERS` names it.
pub const LAYER_NAME: &str = "VK_LAYER_NOSTENCIL_fillrate";

/// File name of the manifest the build writes beside the library.
pub const MANIFEST_FILE: &str = "VkLayer_nostencil_fillrate.json";

/// File name of the shared library that holds the layer (the `nostencil-fillrate-layer`
/// crate's cdylib).
pub const LIBRARY_FILE: &str = "libnostencil_fillrate.so";

/// File name of the library `profile-app --gl` preloads into a GL program to find its buffer
/// swaps (the `nostencil-gl-swaps` crate's cdylib).
pub const GL_SWAPS_FILE: &str = "libnostencil_gl_swaps.so";

/// The manifest text for a layer library at `library_path` (absolute, or relative to the
/// manifest's folder when it starts with "./").
pub fn manifest_json(library_path: &str) -> String {
    format!(
        "{{\n  \"file_format_version\": \"1.2.0\",\n  \"layer\": {{\n    \"name\": \"{LAYER_NAME}\",\n    \
         \"type\": \"INSTANCE\",\n    \"library_path\": \"{}\",\n    \"api_version\": \"1.3.239\",\n    \
         \"implementation_version\": \"1\",\n    \"description\": \"nostencil fill-rate counters per render pass \
         instance (pipeline statistics, precise occlusion, timestamps, tile traffic)\",\n    \
         \"device_extensions\": [{{ \"name\": \"VK_EXT_frame_boundary\", \"spec_version\": \"1\", \
         \"entrypoints\": [] }}]\n  }}\n}}\n",
        json_escape(library_path)
    )
}

/// The layer library to load for a binary in `dir` (`target/<profile>`): the newer of
/// `dir/libnostencil_fillrate.so` and `dir/deps/libnostencil_fillrate.so`. `cargo build` copies the library up to
/// `dir`; `cargo test` builds it only in `deps/`, so the copy in `dir` can be stale there.
pub fn newest_library(dir: &std::path::Path) -> Option<std::path::PathBuf> {
    newest_build_of(dir, LIBRARY_FILE)
}

/// The newer of `dir/FILE` and `dir/deps/FILE` (see [`newest_library`]).
pub fn newest_build_of(dir: &std::path::Path, file: &str) -> Option<std::path::PathBuf> {
    let modified = |p: &std::path::Path| std::fs::metadata(p).and_then(|m| m.modified()).ok();
    [dir.join(file), dir.join("deps").join(file)]
        .into_iter()
        .filter_map(|p| modified(&p).map(|t| (t, p)))
        .max_by_key(|(t, _)| *t)
        .map(|(_, p)| p)
}

/// `text` as the inside of a JSON string.
fn json_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn manifest_is_json_naming_the_layer_and_its_library() {
        let text = manifest_json("/tmp/a \"b\"/libnostencil_fillrate.so");
        let value: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
        assert_eq!(value["file_format_version"], "1.2.0");
        assert_eq!(value["layer"]["name"], LAYER_NAME);
        assert_eq!(value["layer"]["type"], "INSTANCE");
        assert_eq!(value["layer"]["library_path"], "/tmp/a \"b\"/libnostencil_fillrate.so");
        assert_eq!(value["layer"]["implementation_version"], "1");
        assert!(value["layer"]["api_version"].as_str().is_some_and(|v| v.starts_with("1.3.")));
        // The loader accepts the extension the layer offers only if its manifest lists it.
        assert_eq!(value["layer"]["device_extensions"][0]["name"], "VK_EXT_frame_boundary");
    }
}
