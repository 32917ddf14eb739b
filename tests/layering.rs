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

/// Rust source as tokens, without comments, strings and character literals.
mod lexer {
    #[derive(Debug, Clone, PartialEq)]
    pub enum Tok {
        Ident(String),
        /// `::`
        PathSep,
        Punct(char),
    }

    #[derive(Debug, Clone)]
    pub struct Token {
        pub tok: Tok,
        pub line: usize,
    }

    pub fn tokens(source: &str) -> Vec<Token> {
        let chars: Vec<char> = source.chars().collect();
        let mut out = Vec::new();
        let (mut i, mut line) = (0, 1);
        // Skips from `i` to `end`, counting the lines skipped.
        let skip = |i: &mut usize, line: &mut usize, end: usize| {
            *line += chars[*i..end.min(chars.len())].iter().filter(|c| **c == '\n').count();
            *i = end.min(chars.len());
        };
        while i < chars.len() {
            let c = chars[i];
            let next = chars.get(i + 1).copied();
            if c == '/' && next == Some('/') {
                let end = chars[i..].iter().position(|c| *c == '\n').map_or(chars.len(), |p| i + p);
                skip(&mut i, &mut line, end);
            } else if c == '/' && next == Some('*') {
                let end = block_comment_end(&chars, i);
                skip(&mut i, &mut line, end);
            } else if c == '"' {
                let end = string_end(&chars, i + 1);
                skip(&mut i, &mut line, end);
            } else if c == '\'' {
                let end = char_literal_end(&chars, i);
                skip(&mut i, &mut line, end);
            } else if c.is_alphabetic() || c == '_' {
                let start = i;
                while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                    i += 1;
                }
                let word: String = chars[start..i].iter().collect();
                let after = chars.get(i).copied();
                let is_string_prefix = matches!(word.as_str(), "r" | "b" | "br" | "c" | "cr");
                if is_string_prefix && after == Some('"') {
                    let end = string_end(&chars, i + 1);
                    skip(&mut i, &mut line, end);
                } else if is_string_prefix && word != "b" && word != "c" && after == Some('#') {
                    let hashes = chars[i..].iter().take_while(|c| **c == '#').count();
                    if chars.get(i + hashes) == Some(&'"') {
                        let end = raw_string_end(&chars, i + hashes + 1, hashes);
                        skip(&mut i, &mut line, end);
                    } else {
                        i += 1; // r#ident: the identifier follows
                    }
                } else if word == "b" && after == Some('\'') {
                    let end = char_literal_end(&chars, i);
                    skip(&mut i, &mut line, end);
                } else {
                    out.push(Token { tok: Tok::Ident(word), line });
                }
            } else if c.is_ascii_digit() {
                while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                    i += 1;
                }
            } else if c == ':' && next == Some(':') {
                out.push(Token { tok: Tok::PathSep, line });
                i += 2;
            } else {
                if c == '\n' {
                    line += 1;
                } else if !c.is_whitespace() {
                    out.push(Token { tok: Tok::Punct(c), line });
                }
                i += 1;
            }
        }
        out
    }

    /// Just past the `*/` closing the (nestable) block comment opened at `start`.
    fn block_comment_end(chars: &[char], start: usize) -> usize {
        let (mut depth, mut i) = (0, start);
        while i + 1 < chars.len() {
            match (chars[i], chars[i + 1]) {
                ('/', '*') => (depth, i) = (depth + 1, i + 2),
                ('*', '/') => {
                    (depth, i) = (depth - 1, i + 2);
                    if depth == 0 {
                        return i;
                    }
                }
                _ => i += 1,
            }
        }
        chars.len()
    }

    /// Just past the closing quote of a string whose text starts at `i`.
    fn string_end(chars: &[char], mut i: usize) -> usize {
        while i < chars.len() {
            match chars[i] {
                '\\' => i += 2,
                '"' => return i + 1,
                _ => i += 1,
            }
        }
        chars.len()
    }

    /// Just past the `"###` closing a raw string whose text starts at `i`.
    fn raw_string_end(chars: &[char], mut i: usize, hashes: usize) -> usize {
        while i < chars.len() {
            if chars[i] == '"' && chars[i + 1..].iter().take(hashes).filter(|c| **c == '#').count() == hashes {
                return i + 1 + hashes;
            }
            i += 1;
        }
        chars.len()
    }

    /// At a `'`: just past the character literal it opens, or just past the `'` of a lifetime
    /// or label (whose name is then read as an identifier).
    fn char_literal_end(chars: &[char], start: usize) -> usize {
        match (chars.get(start + 1), chars.get(start + 2)) {
            (Some('\\'), _) => {
                let close = chars[start + 3..].iter().position(|c| *c == '\'');
                close.map_or(chars.len(), |p| start + 3 + p + 1)
            }
            (Some(_), Some('\'')) => start + 3,
            _ => start + 1,
        }
    }
}

/// The paths a file names: the leaves of its `use` trees, and `crate::`/`super::` paths in
/// expressions, each with its line and the inline modules (`mod tests { .. }`) it sits in.
mod paths {
    use super::lexer::{Tok, Token};

    #[derive(Debug, Clone)]
    pub struct NamedPath {
        pub line: usize,
        /// As written, groups expanded: `crate`, `frame`, `RgbaImage`.
        pub segments: Vec<String>,
        /// `use a::B as C` names it `C`.
        pub alias: Option<String>,
        /// A `pub use` (a re-export), which other files may import through this one.
        pub reexport: bool,
        /// Inline modules around it, outermost first: `super` climbs these first.
        pub inline_modules: Vec<String>,
    }

    impl NamedPath {
        pub fn text(&self) -> String {
            self.segments.join("::")
        }
    }

    pub fn named_paths(tokens: &[Token]) -> Vec<NamedPath> {
        let mut out = Vec::new();
        let mut modules: Vec<(String, usize)> = Vec::new();
        let (mut i, mut depth) = (0, 0usize);
        let ident = |i: usize| match tokens.get(i).map(|t| &t.tok) {
            Some(Tok::Ident(name)) => Some(name.as_str()),
            _ => None,
        };
        let is = |i: usize, tok: Tok| tokens.get(i).is_some_and(|t| t.tok == tok);
        while i < tokens.len() {
            let inline_modules: Vec<String> = modules.iter().map(|(name, _)| name.clone()).collect();
            if ident(i) == Some("mod") && ident(i + 1).is_some() && is(i + 2, Tok::Punct('{')) {
                modules.push((ident(i + 1).unwrap_or_default().to_owned(), depth));
                depth += 1;
                i += 3;
            } else if is(i, Tok::Punct('{')) {
                depth += 1;
                i += 1;
            } else if is(i, Tok::Punct('}')) {
                depth = depth.saturating_sub(1);
                if modules.last().is_some_and(|(_, d)| *d == depth) {
                    modules.pop();
                }
                i += 1;
            } else if ident(i) == Some("use") {
                // `pub use`, `pub(crate) use`: a re-export.
                let reexport = i > 0 && (ident(i - 1) == Some("pub") || is(i - 1, Tok::Punct(')')));
                let start = if is(i + 1, Tok::PathSep) { i + 2 } else { i + 1 };
                let line = tokens[i].line;
                let mut leaves = Vec::new();
                i = use_tree(tokens, start, Vec::new(), &mut leaves);
                for (segments, alias) in leaves {
                    let inline_modules = inline_modules.clone();
                    out.push(NamedPath { line, segments, alias, reexport, inline_modules });
                }
            } else if matches!(ident(i), Some("crate" | "super"))
                && is(i + 1, Tok::PathSep)
                && !(i > 0 && (is(i - 1, Tok::PathSep) || is(i - 1, Tok::Punct('$'))))
            {
                let line = tokens[i].line;
                let mut leaves = Vec::new();
                i = use_tree(tokens, i, Vec::new(), &mut leaves);
                for (segments, alias) in leaves {
                    let inline_modules = inline_modules.clone();
                    out.push(NamedPath { line, segments, alias, reexport: false, inline_modules });
                }
            } else {
                i += 1;
            }
        }
        out
    }

    /// Reads a path or a `use` tree at `i` under `prefix`; pushes each leaf (and its alias).
    /// Returns the index after it.
    fn use_tree(
        tokens: &[Token],
        mut i: usize,
        prefix: Vec<String>,
        out: &mut Vec<(Vec<String>, Option<String>)>,
    ) -> usize {
        let tok = |i: usize| tokens.get(i).map(|t| &t.tok);
        match tok(i) {
            Some(Tok::Punct('{')) => {
                i += 1;
                while i < tokens.len() && tok(i) != Some(&Tok::Punct('}')) {
                    let before = i;
                    i = use_tree(tokens, i, prefix.clone(), out);
                    if tok(i) == Some(&Tok::Punct(',')) {
                        i += 1;
                    } else if i == before {
                        i += 1; // something unexpected: step over it
                    }
                }
                i + 1
            }
            Some(Tok::Punct('*')) => {
                out.push(([prefix, vec!["*".to_owned()]].concat(), None));
                i + 1
            }
            Some(Tok::Ident(name)) => {
                let mut segments = prefix.clone();
                if tok(i + 1) == Some(&Tok::PathSep) {
                    segments.push(name.clone());
                    return use_tree(tokens, i + 2, segments, out);
                }
                // `a::{self, B}` names `a` itself.
                if name != "self" || prefix.is_empty() {
                    segments.push(name.clone());
                }
                i += 1;
                let mut alias = None;
                if let (Some(Tok::Ident(word)), Some(Tok::Ident(name))) = (tok(i), tok(i + 1)) {
                    if word == "as" {
                        alias = Some(name.clone());
                        i += 2;
                    }
                }
                out.push((segments, alias));
                i
            }
            // A turbofish or anything else ends the path here.
            _ => {
                if !prefix.is_empty() {
                    out.push((prefix, None));
                }
                i
            }
        }
    }
}

/// The source files as modules: which file is which module, what each names, what each
/// re-exports, and how a path resolves to a top-level module and to a file.
mod tree {
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
            let modules = files
                .iter()
                .enumerate()
                .filter(|(_, f)| f.path != "main.rs")
                .map(|(i, f)| (f.module.clone(), i))
                .collect();
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
}

/// The two rules, each returning its problems as messages.
mod rules {
    use super::tree::SourceTree;
    use super::{BTreeMap, BTreeSet, LAYERS, SAME_LAYER_ALLOWED};

    fn layer_of(module: &str) -> Option<usize> {
        LAYERS.iter().position(|layer| layer.contains(&module))
    }

    /// Why `importer` may not import `imported`, or None when it may.
    fn forbidden(importer: &str, imported: Option<&str>) -> Option<String> {
        let Some(imported) = imported else { return Some("the crate root, above every layer".into()) };
        if importer == imported || SAME_LAYER_ALLOWED.contains(&(importer, imported)) {
            return None;
        }
        match (layer_of(importer), layer_of(imported)) {
            (Some(a), Some(b)) if b < a => None,
            (Some(a), Some(b)) if b == a => Some(format!("{imported}, in the same layer")),
            (Some(_), Some(_)) => Some(format!("{imported}, a layer above")),
            (None, _) => Some(format!("{importer} is in no layer of LAYERS")),
            (_, None) => Some(format!("{imported}, which is in no layer of LAYERS")),
        }
    }

    /// Every import of a module from a layer above its own or beside it, one message per
    /// file, line and imported module: `src/gpu/texture.rs:12: gpu imports frame, a layer
    /// above: crate::frame::RgbaImage`.
    pub fn layer_violations(tree: &SourceTree) -> Vec<String> {
        let mut found: BTreeMap<(String, usize, String, String), BTreeSet<String>> = BTreeMap::new();
        for file in tree.files.iter().filter(|f| !f.is_root()) {
            let Some(importer) = file.top() else { continue };
            for path in &file.paths {
                let Some(absolute) = tree.absolute(file, path) else { continue };
                let imported = tree.top_module(&absolute);
                if let Some(why) = forbidden(importer, imported.as_deref()) {
                    let key = (file.path.clone(), path.line, importer.to_owned(), why);
                    found.entry(key).or_default().insert(path.text());
                }
            }
        }
        found
            .into_iter()
            .map(|((file, line, importer, why), imports)| {
                let imports: Vec<String> = imports.into_iter().collect();
                format!("src/{file}:{line}: {importer} imports {why}: {}", imports.join(", "))
            })
            .collect()
    }

    /// The import edges between the files of one top-level module: (from, to) -> the
    /// imports that make the edge, as (line, `src/file:line: path`).
    fn file_graph(tree: &SourceTree) -> BTreeMap<(usize, usize), BTreeSet<(usize, String)>> {
        let mut edges: BTreeMap<(usize, usize), BTreeSet<(usize, String)>> = BTreeMap::new();
        for (from, file) in tree.files.iter().enumerate().filter(|(_, f)| !f.is_root()) {
            for path in &file.paths {
                // `super::` and `crate::` paths make edges; a parent's bare `child::x` and
                // `self::x` are how a module uses its own children. An inline module
                // (`mod tests { .. }`) is a module of its own that no file imports, so it
                // cannot close a circle: its imports count for the layers only.
                let relative = !matches!(path.segments.first().map(String::as_str), Some("super" | "crate"));
                if relative || !path.inline_modules.is_empty() {
                    continue;
                }
                let Some(absolute) = tree.absolute(file, path) else { continue };
                let Some(to) = tree.resolve(&absolute, 0) else { continue };
                if to != from && tree.files[to].top() == file.top() {
                    let site = format!("src/{}:{}: {}", file.path, path.line, path.text());
                    edges.entry((from, to)).or_default().insert((path.line, site));
                }
            }
        }
        edges
    }

    /// The shortest way from `start` back to itself along `next`, as the files on it.
    fn shortest_circle(next: &[Vec<usize>], start: usize) -> Option<Vec<usize>> {
        let mut came_from: BTreeMap<usize, usize> = BTreeMap::new();
        let mut queue = std::collections::VecDeque::from([start]);
        while let Some(node) = queue.pop_front() {
            for &to in &next[node] {
                if to == start {
                    let mut circle = vec![node];
                    while let Some(&before) = came_from.get(circle.last()?) {
                        circle.push(before);
                    }
                    circle.reverse();
                    return Some(circle);
                }
                if to != start && !came_from.contains_key(&to) {
                    came_from.insert(to, node);
                    queue.push_back(to);
                }
            }
        }
        None
    }

    /// Each group of files inside one top-level module that import each other round in a
    /// circle (a strongly connected component): its files, and the shortest circle through
    /// each of them with one import per step.
    pub fn circles(tree: &SourceTree) -> Vec<String> {
        let edges = file_graph(tree);
        let n = tree.files.len();
        let mut next: Vec<Vec<usize>> = vec![Vec::new(); n];
        for (from, to) in edges.keys() {
            next[*from].push(*to);
        }
        let circle_through: Vec<Option<Vec<usize>>> = (0..n).map(|start| shortest_circle(&next, start)).collect();
        let reaches = |a: usize, b: usize| {
            let (mut seen, mut stack) = (BTreeSet::from([a]), vec![a]);
            while let Some(node) = stack.pop() {
                stack.extend(next[node].iter().filter(|to| seen.insert(**to)));
            }
            seen.contains(&b)
        };
        let name = |file: usize| tree.files[file].path.as_str();
        let mut placed = vec![false; n];
        let mut problems = Vec::new();
        for a in (0..n).filter(|a| circle_through[*a].is_some()) {
            if placed[a] {
                continue;
            }
            let group: Vec<usize> = (a..n).filter(|b| reaches(a, *b) && reaches(*b, a)).collect();
            let names: Vec<&str> = group.iter().map(|f| name(*f)).collect();
            let top = tree.files[a].top().unwrap_or_default();
            let mut message = format!("circle in {top}/ between {}:", names.join(", "));
            let mut shown: BTreeSet<Vec<usize>> = BTreeSet::new();
            for &b in &group {
                placed[b] = true;
                let Some(circle) = circle_through[b].clone() else { continue };
                // The same circle found from another of its files.
                let mut key = circle.clone();
                key.sort();
                if !shown.insert(key) {
                    continue;
                }
                let steps: Vec<&str> = circle.iter().chain(&circle[..1]).map(|f| name(*f)).collect();
                message.push_str(&format!("\n    {}", steps.join(" -> ")));
                for (i, from) in circle.iter().enumerate() {
                    let to = circle[(i + 1) % circle.len()];
                    if let Some((_, site)) = edges.get(&(*from, to)).and_then(|sites| sites.first()) {
                        message.push_str(&format!("\n        {site}"));
                    }
                }
            }
            problems.push(message);
        }
        problems
    }
}

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
