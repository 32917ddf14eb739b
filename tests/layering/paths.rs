//! The paths a file names: the leaves of its `use` trees, and `crate::`/`super::` paths in
//! expressions, each with its line and the inline modules (`mod tests { .. }`) it sits in.

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
