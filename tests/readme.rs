//! The documentation stays true to the program and to itself: the README's command table lists
//! exactly the subcommands `nostencil --help` prints, its techniques table exactly the
//! techniques `nostencil info --json` lists, each with the one-line description `nostencil
//! passes` prints; docs/command-line.md's usage block names every subcommand; docs/tests.md has
//! a row for every file of tests/; and every relative link in README.md and docs/ leads to a file
//! that exists, and to a heading that exists when it names one.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn read(relative: &str) -> String {
    std::fs::read_to_string(root().join(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"))
}

/// `nostencil ARGS`'s standard output; the command must succeed.
fn nostencil(args: &[&str]) -> String {
    let output = Command::new(env!("CARGO_BIN_EXE_nostencil")).args(args).output().expect("nostencil runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "nostencil {}: {}\n{stderr}", args.join(" "), output.status);
    String::from_utf8(output.stdout).expect("UTF-8 output")
}

/// The rows of the first Markdown table after the heading `heading`, as trimmed cells (header
/// and separator rows left out).
fn table_after(markdown: &str, heading: &str) -> Vec<Vec<String>> {
    let start = markdown.lines().position(|l| l.trim_end() == heading).unwrap_or_else(|| panic!("no '{heading}'"));
    let rows: Vec<Vec<String>> = markdown
        .lines()
        .skip(start + 1)
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .map(|l| l.trim().trim_matches('|').split('|').map(|c| c.trim().to_string()).collect())
        .collect();
    assert!(rows.len() > 2, "'{heading}' has no table");
    rows[2..].to_vec()
}

/// A cell written as `` `name` ``, without its backticks.
fn code_cell(cell: &str) -> String {
    cell.strip_prefix('`').and_then(|c| c.strip_suffix('`')).unwrap_or_else(|| panic!("'{cell}' is not `code`")).into()
}

/// The subcommands `nostencil --help` lists, in its order (clap's own `help` left out).
fn subcommands() -> Vec<String> {
    let help = nostencil(&["--help"]);
    let names: Vec<String> = help
        .lines()
        .skip_while(|l| l.trim() != "Commands:")
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        // A wrapped description is indented deeper than a command's name.
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(String::from)
        .collect();
    assert!(names.len() >= 5, "no commands in --help:\n{help}");
    names
}

#[test]
fn the_readme_command_table_is_the_help() {
    let readme = read("README.md");
    let listed: Vec<String> = table_after(&readme, "## Commands").iter().map(|row| code_cell(&row[0])).collect();
    let commands = subcommands();
    assert_eq!(
        listed, commands,
        "README.md's command table (left) is not `nostencil --help`'s list (right): add or remove rows, in that order"
    );
}

#[test]
fn the_command_line_page_shows_every_command() {
    let page = read("docs/command-line.md");
    let usage: Vec<&str> =
        page.lines().filter_map(|l| l.strip_prefix("nostencil ")?.split_whitespace().next()).collect();
    let commands = subcommands();
    for command in &commands {
        assert!(usage.contains(&command.as_str()), "docs/command-line.md has no usage line for `{command}`");
    }
    for name in usage {
        assert!(commands.iter().any(|c| c == name), "docs/command-line.md shows `{name}`, which --help does not list");
    }
}

#[test]
fn the_readme_technique_table_is_info() {
    let info: serde_json::Value = serde_json::from_str(&nostencil(&["info", "--json"])).expect("info --json is JSON");
    let techniques: Vec<(String, String)> = info["techniques"]
        .as_array()
        .expect("info --json lists techniques")
        .iter()
        .map(|t| {
            let name = t.as_str().expect("a technique's name").to_string();
            // `passes` prints "## NAME: passes ...", a blank line, then the technique's one line.
            let passes = nostencil(&["passes", "--technique", &name]);
            let about = passes.lines().nth(2).unwrap_or_default().trim().to_string();
            assert!(!about.is_empty(), "`passes --technique {name}` printed no description");
            (name, about)
        })
        .collect();
    assert!(techniques.len() >= 5, "{techniques:?}");
    let readme = read("README.md");
    let listed: Vec<(String, String)> =
        table_after(&readme, "## Techniques").iter().map(|row| (code_cell(&row[0]), row[1].clone())).collect();
    let expected: Vec<String> = techniques.iter().map(|(name, about)| format!("| `{name}` | {about} |")).collect();
    assert_eq!(
        listed,
        techniques,
        "README.md's techniques table (left) is not `nostencil info`'s techniques with their descriptions \
         (right); its first two columns should read:\n{}",
        expected.join("\n")
    );
}

#[test]
fn docs_tests_has_a_row_for_every_test_file() {
    let page = read("docs/tests.md");
    let rows: Vec<String> =
        table_after(&page, "## What each test file proves").iter().map(|row| code_cell(&row[0])).collect();
    // The integration suite's files, and those compiled into the library as `inside/NAME.rs`.
    let rust_files = |folder: &str, prefix: &str| -> Vec<String> {
        std::fs::read_dir(root().join(folder))
            .unwrap_or_else(|e| panic!("{folder}: {e}"))
            .flatten()
            .map(|e| format!("{prefix}{}", e.file_name().to_string_lossy()))
            .filter(|name| name.ends_with(".rs"))
            .collect()
    };
    let mut files = rust_files("tests", "");
    files.extend(rust_files("tests/inside", "inside/"));
    files.sort();
    let missing: Vec<&String> = files.iter().filter(|f| !rows.contains(f)).collect();
    let gone: Vec<&String> = rows.iter().filter(|r| !files.contains(r)).collect();
    assert!(missing.is_empty(), "docs/tests.md has no row for {missing:?}");
    assert!(gone.is_empty(), "docs/tests.md has rows for files that are not in tests/: {gone:?}");
}

/// README.md and every Markdown file below docs/.
fn markdown_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("docs/").flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    let mut files = vec![root().join("README.md")];
    walk(&root().join("docs"), &mut files);
    files.sort();
    files
}

/// The text outside fenced code blocks and inline code spans: links there are not links.
fn prose(markdown: &str) -> String {
    let mut text = String::new();
    let mut fenced = false;
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced {
            text.push_str(line);
            text.push('\n');
        }
    }
    // Inline code may run over a line break, so it is removed from the whole text.
    let mut outside = String::new();
    for (i, piece) in text.split('`').enumerate() {
        if i % 2 == 0 {
            outside.push_str(piece);
        }
    }
    outside
}

/// The anchors GitHub gives the headings of a Markdown file: lower case, spaces to hyphens,
/// punctuation other than `-` and `_` dropped, repeats numbered `-1`, `-2`...
fn anchors(markdown: &str) -> Vec<String> {
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut fenced = false;
    let mut out = Vec::new();
    for line in markdown.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        let Some(title) = line.strip_prefix('#').filter(|_| !fenced).map(|t| t.trim_start_matches('#')) else {
            continue;
        };
        if !title.starts_with(' ') {
            continue;
        }
        let slug: String = title
            .trim()
            .to_lowercase()
            .chars()
            .filter(|c| c.is_alphanumeric() || *c == '-' || *c == '_' || *c == ' ')
            .map(|c| if c == ' ' { '-' } else { c })
            .collect();
        let n = seen.entry(slug.clone()).or_insert(0);
        out.push(if *n == 0 { slug.clone() } else { format!("{slug}-{n}") });
        *n += 1;
    }
    out
}

/// The targets of the inline links and images in `markdown`'s prose: `[text](target)`.
fn link_targets(markdown: &str) -> Vec<String> {
    let text = prose(markdown);
    text.match_indices("](")
        .filter_map(|(at, _)| {
            let rest = &text[at + 2..];
            let end = rest.find(')')?;
            let target = rest[..end].split_whitespace().next()?;
            Some(target.trim_matches(|c| c == '<' || c == '>').to_string())
        })
        .collect()
}

#[test]
fn relative_links_lead_to_files_and_headings_that_exist() {
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in markdown_files() {
        let text = std::fs::read_to_string(&file).expect("readable Markdown");
        let name = file.strip_prefix(root()).expect("inside the checkout").display().to_string();
        for target in link_targets(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            checked += 1;
            let (path, anchor) = target.split_once('#').map_or((target.as_str(), None), |(p, a)| (p, Some(a)));
            let resolved = if path.is_empty() { file.clone() } else { file.parent().expect("a folder").join(path) };
            if !resolved.exists() {
                broken.push(format!("{name}: ({target}): no file {}", resolved.display()));
                continue;
            }
            if let Some(anchor) = anchor {
                let heads = std::fs::read_to_string(&resolved).map(|t| anchors(&t)).unwrap_or_default();
                if !heads.iter().any(|h| h == anchor) {
                    broken.push(format!("{name}: ({target}): no heading #{anchor}; there are {heads:?}"));
                }
            }
        }
    }
    assert!(checked > 100, "only {checked} relative links found: is the link parser broken?");
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn headings_become_githubs_anchors() {
    let page =
        "# A title\n## How it is checked (tests/profile_app.rs)\n```\n# not a heading\n```\n## A title\n#hashtag\n";
    assert_eq!(anchors(page), ["a-title", "how-it-is-checked-testsprofile_apprs", "a-title-1"]);
    assert_eq!(link_targets("see [a](b.md#c) and `[d](e.md)`, ![f](g.png \"t\")"), ["b.md#c", "g.png"]);
}

#[test]
fn the_walkthrough_quotes_the_code_it_walks_through() {
    let page = read("docs/adding-a-technique.md");
    let sources = [read("src/technique/xray/mod.rs"), read("src/technique/registry.rs")].join("\n");
    let mut blocks = Vec::new();
    let mut current: Option<Vec<&str>> = None;
    for line in page.lines() {
        match (&mut current, line.trim_start()) {
            (None, "```rust") => current = Some(Vec::new()),
            (Some(block), "```") => {
                blocks.push(block.join("\n"));
                current = None;
            }
            (Some(block), _) => block.push(line),
            _ => {}
        }
    }
    assert!(blocks.len() >= 5, "the walkthrough shows only {} code blocks", blocks.len());
    for block in &blocks {
        assert!(
            sources.contains(block.as_str()),
            "docs/adding-a-technique.md quotes code the source no longer has:\n{block}"
        );
    }
    // The line count it gives is the folder's.
    let lines = read("src/technique/xray/mod.rs").lines().count();
    assert!(
        page.contains(&format!("`src/technique/xray/mod.rs` ({lines} lines")),
        "the walkthrough's line count is not {lines}"
    );
}
