//! The source files as modules: which file is which module, what each names, what each
//! re-exports, and how a path resolves to a top-level module and to a file.

use std::collections::BTreeMap;

use super::lexer::tokens;
use super::paths::{named_paths, NamedPath};
use super::{CRATE_ROOTS, LAYERS};

pub struct SourceFile {
    /// Path under src/, as `scene/rig.rs`.
    pub path: String,
    /// Module path: `scene/rig.rs` and `scene/rig/mod.rs` are `["scene", "rig"]`.
    pub module: Vec<String>,
    pub paths: Vec<NamedPath>,
}

impl SourceFile {
    pub fn is_root(&self) -> bool {
        CRATE_ROOTS.contains(&self.path.as_str())
    }

    /// The top-level module it belongs to.
    pub fn top(&self) -> Option<&str> {
        self.module.first().map(String::as_str)
    }
}

pub struct SourceTree {
    pub files: Vec<SourceFile>,
    modules: BTreeMap<Vec<String>, usize>,
}

impl SourceTree {
    pub fn new(sources: &[(String, String)]) -> Self {
        let files: Vec<SourceFile> = sources
            .iter()
            .map(|(path, text)| SourceFile {
                path: path.clone(),
                module: module_of(path),
                paths: named_paths(&tokens(text)),
            })
            .collect();
        // main.rs is a crate of its own: only lib.rs is the library's root module.
        let modules =
            files.iter().enumerate().filter(|(_, f)| f.path != "main.rs").map(|(i, f)| (f.module.clone(), i)).collect();
        SourceTree { files, modules }
    }

    /// The absolute module path `path` (written in `file`) names, or None for paths that
    /// are not the crate's (`std::`, `ash::`) or climb above the crate root.
    pub fn absolute(&self, file: &SourceFile, path: &NamedPath) -> Option<Vec<String>> {
        let segments = &path.segments;
        let first = segments.first()?.as_str();
        let mut here: Vec<String> = file.module.iter().chain(&path.inline_modules).cloned().collect();
        match first {
            "crate" => Some(segments[1..].to_vec()),
            "self" => Some([here, segments[1..].to_vec()].concat()),
            "super" => {
                let climbs = segments.iter().take_while(|s| *s == "super").count();
                for _ in 0..climbs {
                    here.pop()?;
                }
                Some([here, segments[climbs..].to_vec()].concat())
            }
            // Relative: a child module of this one (`use live::Settings` in viewer/mod.rs).
            _ if self.modules.contains_key(&[here.clone(), vec![first.to_owned()]].concat()) => {
                Some([here, segments.clone()].concat())
            }
            _ => None,
        }
    }

    /// The top-level module an absolute path lands in, following the crate root's
    /// re-exports (`crate::Error` is `crate::error::Error`); None for the crate root itself.
    pub fn top_module(&self, absolute: &[String]) -> Option<String> {
        let landed = self.resolve(absolute, 0).and_then(|file| self.files[file].top());
        // A module named in LAYERS without a file (only in made-up trees) is still itself.
        let named = absolute.first().filter(|first| LAYERS.iter().any(|layer| layer.contains(&first.as_str())));
        landed.or(named.map(String::as_str)).map(str::to_owned)
    }

    /// The file an absolute path lands in: the deepest module file it names, following
    /// `pub use` re-exports of the module files on the way (`crate::scene::Scene` is
    /// defined in scene/objects.rs).
    pub fn resolve(&self, absolute: &[String], depth: usize) -> Option<usize> {
        let mut current = *self.modules.get(&Vec::new())?;
        for i in 0..absolute.len() {
            if let Some(file) = self.modules.get(&absolute[..=i]) {
                current = *file;
                continue;
            }
            if depth < 8 {
                if let Some(target) = self.reexport(current, &absolute[i]) {
                    if let Some(file) = self.resolve(&target, depth + 1) {
                        return Some(file);
                    }
                }
            }
            break;
        }
        Some(current)
    }

    /// Where a name `file` re-exports with `pub use` points, as an absolute path.
    fn reexport(&self, file: usize, name: &str) -> Option<Vec<String>> {
        let source = &self.files[file];
        source.paths.iter().filter(|p| p.reexport && p.inline_modules.is_empty()).find_map(|p| {
            let exported = p.alias.as_deref().or(p.segments.last().map(String::as_str))?;
            (exported == name).then(|| self.absolute(source, p)).flatten()
        })
    }
}

fn module_of(path: &str) -> Vec<String> {
    if CRATE_ROOTS.contains(&path) {
        return Vec::new();
    }
    let mut parts: Vec<String> = path.trim_end_matches(".rs").split('/').map(str::to_owned).collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}
