//! The layering rule, checked on the source: a module of the renderer imports only from layers
//! below its own, never from one beside it or above it, and the files inside one top-level
//! module (and the fill-rate layer's crate) import each other without circles. `cargo doc` and
//! the compiler accept both mistakes, so they are caught here, with every offending file:line in
//! the failure message. Between crates the compiler itself enforces the rule: the layer's crate
//! and the report's cannot name the renderer, which does not name the layer.
//!
//! Imports are found on tokens, not text: comments, strings and character literals are skipped,
//! `use crate::{a, b::c}` groups are expanded, `crate::x::f()` in expressions counts, and so do
//! `super::` chains that climb out of a top-level module. `#[cfg(test)]` modules count too.
//! The lexer, the paths, the module tree and the rules are submodules in `layering/`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Top-level modules bottom to top. A module may import from the layers below its own only.
const LAYERS: &[&[&str]] = &[
    &["names"],
    &["error", "shaders"],
    &["gpu"],
    &["mesh"],
    &["scene"],
    &["frame"],
    &["pipeline"],
    &["render"],
    &["technique"],
    &["sample"],
    &["profile"],
    &["viewer"],
    &["cli"],
];

/// The exceptions to "one layer may not import itself": (importer, imported).
const SAME_LAYER_ALLOWED: &[(&str, &str)] = &[("shaders", "error")];

/// The crate roots: above every layer, they assemble the crate and may import anything.
const CRATE_ROOTS: &[&str] = &["lib.rs", "main.rs"];

#[test]
fn no_module_imports_from_a_layer_above_or_beside_it_and_no_module_has_circles() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    collect_rust_files(&src, &src, &mut files);
    assert!(files.len() > 20, "only {} source files found under {}", files.len(), src.display());
    let problems = check(&files);
    assert!(problems.is_empty(), "{} layering problem(s):\n{}", problems.len(), problems.join("\n"));
}

#[test]
fn the_fill_rate_layers_modules_have_no_circles() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/fillrate-layer/src");
    let mut files = Vec::new();
    collect_rust_files(&src, &src, &mut files);
    assert!(files.len() > 20, "only {} source files found under {}", files.len(), src.display());
    // Its modules as the one top-level module `layer` they were inside the renderer: its own
    // `crate::` is that module.
    let files: Vec<(String, String)> = files
        .into_iter()
        .map(|(path, text)| {
            let path = if path == "lib.rs" { "layer/mod.rs".to_owned() } else { format!("layer/{path}") };
            (path, text.replace("crate::", "crate::layer::"))
        })
        .collect();
    let tree = tree::SourceTree::new(&files);
    let problems = rules::circles(&tree);
    assert!(problems.is_empty(), "{} circle(s) in the layer:\n{}", problems.len(), problems.join("\n"));
}

/// Every `.rs` file under `dir` as (path relative to `root`, with '/', and its text).
fn collect_rust_files(root: &Path, dir: &Path, out: &mut Vec<(String, String)>) {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    let mut paths: Vec<_> = entries.map(|e| e.unwrap_or_else(|e| panic!("{}: {e}", dir.display())).path()).collect();
    paths.sort();
    for path in paths {
        if path.is_dir() {
            collect_rust_files(root, &path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let relative = path.strip_prefix(root).unwrap_or(&path);
            let name = relative.components().map(|c| c.as_os_str().to_string_lossy()).collect::<Vec<_>>().join("/");
            out.push((name, text));
        }
    }
}

/// The problems of a source tree given as (path under src/, text): layer violations, then
/// circles, one message each (a circle's message lists the imports that close it).
fn check(files: &[(String, String)]) -> Vec<String> {
    let tree = tree::SourceTree::new(files);
    let mut problems = rules::layer_violations(&tree);
    problems.extend(rules::circles(&tree));
    problems
}

// In layering/: the source as tokens, the paths each file names, the files as a module tree,
// and the two rules over it.
mod lexer;
mod paths;
mod rules;
mod tree;

/// The detector itself, on small made-up trees: it must catch what it claims and nothing else.
#[test]
fn the_detector_catches_upward_grouped_expression_and_climbing_imports_and_circles_only() {
    let source = |path: &str, text: &str| (path.to_owned(), text.to_owned());
    let files = [
        source("lib.rs", "pub mod error;\npub mod gpu;\npub mod frame;\npub use error::{Error, Result};\n"),
        source("error.rs", "pub struct Error;\n"),
        source("shaders.rs", "use crate::error::Error;\n"),
        // An upward import, one inside a `{}` group, and one in an expression.
        source("gpu/mod.rs", "pub mod texture;\npub use texture::Texture;\n"),
        source(
            "gpu/texture.rs",
            "use crate::frame::RgbaImage;\n\
             use crate::{Error, mesh::{weld, shapes::MeshData}, render::Renderer};\n\
             fn f() { let _ = crate::technique::lit::draw(); }\n",
        ),
        // Never an import: comments, doc links, strings, raw strings and char literals.
        source(
            "mesh/mod.rs",
            "// use crate::cli::Cli;\n\
             /* crate::viewer::View /* nested */ crate::cli::X */\n\
             /// See [`run`](crate::cli::run).\n\
             const A: &str = \"crate::cli::run \\\" crate::viewer\";\n\
             const B: &str = r#\"use crate::profile::X; \"# ;\n\
             const C: char = '\"'; const D: char = '\\''; fn g<'a>(x: &'a str) -> &'a str { x }\n\
             use crate::gpu::Gpu;\n\
             use crate::error::Result as R;\n",
        ),
        // Same layer: error may not import shaders; shaders may import error.
        source("error/detail.rs", "use crate::shaders::spirv;\n"),
        // A `super` chain that climbs out of scene, from a test module.
        source(
            "scene/mod.rs",
            "pub mod a;\npub mod b;\npub mod c;\npub use a::A;\npub use b::B;\nuse super::gpu::Gpu;\n",
        ),
        source("scene/a.rs", "use super::b::B;\n#[cfg(test)]\nmod tests {\n    use super::super::super::viewer::View;\n    use super::*;\n}\n"),
        // a -> b -> a through the module's re-export.
        source("scene/b.rs", "use crate::scene::A;\nfn f() -> u32 { 3 }\nmod tests {\n    use crate::scene::c;\n}\n"),
        // c -> a alone, and b's test module -> c: no circle.
        source("scene/c.rs", "use super::A;\n"),
        source("frame/mod.rs", "pub struct RgbaImage;\n"),
    ];
    let problems = check(&files);
    let expected = [
        "src/error/detail.rs:1: error imports shaders, in the same layer: crate::shaders::spirv",
        "src/gpu/texture.rs:1: gpu imports frame, a layer above: crate::frame::RgbaImage",
        "src/gpu/texture.rs:2: gpu imports mesh, a layer above: crate::mesh::shapes::MeshData, crate::mesh::weld",
        "src/gpu/texture.rs:2: gpu imports render, a layer above: crate::render::Renderer",
        "src/gpu/texture.rs:3: gpu imports technique, a layer above: crate::technique::lit::draw",
        "src/scene/a.rs:4: scene imports viewer, a layer above: super::super::super::viewer::View",
        "circle in scene/ between scene/a.rs, scene/b.rs:\n    \
         scene/a.rs -> scene/b.rs -> scene/a.rs\n        \
         src/scene/a.rs:1: super::b::B\n        \
         src/scene/b.rs:1: crate::scene::A",
    ];
    assert_eq!(problems, expected, "\n{}", problems.join("\n"));
}
