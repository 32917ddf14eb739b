//! The repository stands alone: a user's clone has nothing beside it, so no file may name a path
//! outside the checkout, and every real asset the tests read is in `tests/assets` with its origin
//! and licence in `tests/assets/SOURCES.md`. CI runs the suite in a clone with nothing beside it
//! (`.ci/run`); these checks say *which* file broke the rule before a test fails for a missing
//! file.

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every file below `dir`, skipping build output and the generated shader-compiler archive.
fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name();
        if name == "target" || name == "shaderc-lib" || name == ".git" {
            continue;
        }
        if path.is_dir() {
            files(&path, out);
        } else {
            out.push(path);
        }
    }
}

#[test]
fn no_file_names_a_folder_beside_the_checkout() {
    // Built at run time, so that this file does not match itself.
    let needles = [format!("../{}", "shared"), format!("..\\{}", "shared")];
    let mut all = Vec::new();
    for top in ["src", "tests", "tools", "shaders", "docs", "examples", ".ci", ".cargo"] {
        files(&root().join(top), &mut all);
    }
    all.extend(["README.md", "build.rs", "Cargo.toml"].map(|f| root().join(f)));
    let mut offending = Vec::new();
    for path in &all {
        let Ok(text) = std::fs::read_to_string(path) else { continue };
        for (number, line) in text.lines().enumerate() {
            if needles.iter().any(|n| line.contains(n.as_str())) {
                offending.push(format!("{}:{}: {}", path.display(), number + 1, line.trim()));
            }
        }
    }
    assert!(all.len() > 100, "only {} files read", all.len());
    assert!(offending.is_empty(), "paths outside the repository:\n{}", offending.join("\n"));
}

#[test]
fn every_test_asset_has_its_origin_and_licence_in_sources() {
    let assets = root().join("tests/assets");
    let sources = std::fs::read_to_string(assets.join("SOURCES.md")).expect("tests/assets/SOURCES.md");
    let mut all = Vec::new();
    files(&assets, &mut all);
    let mut missing = Vec::new();
    let mut listed = 0;
    for path in &all {
        let relative = path.strip_prefix(&assets).expect("below assets").to_string_lossy().replace('\\', "/");
        if relative == "SOURCES.md" || relative.starts_with("licenses/") {
            continue;
        }
        listed += 1;
        // A file is named itself, or through its folder (`blender/01_unlit/`).
        let folder = relative.rsplit_once('/').map(|(dir, _)| format!("`{dir}/`"));
        let named = sources.contains(&format!("`{relative}`")) || folder.is_some_and(|f| sources.contains(&f));
        if !named {
            missing.push(relative);
        }
    }
    assert!(listed >= 15, "{listed} assets");
    assert!(missing.is_empty(), "assets without a line in SOURCES.md: {missing:?}");
    for licence in ["Apache-2.0.txt", "CC0-1.0.txt", "MIT-glTF-Transform.txt"] {
        assert!(assets.join("licenses").join(licence).is_file(), "licence text {licence} missing");
    }
}
