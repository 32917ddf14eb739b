//! The two rules, each returning its problems as messages.

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
