//! One self-contained HTML page per run (`--html FILE`): a banner, charts, tables, findings and
//! images, with the run's JSON embedded. Everything is inline (styles, SVG, PNGs as data URIs)
//! and nothing runs: the page opens from disk, travels as a CI artifact or an e-mail, and prints.

use std::fmt::Write as _;
use std::path::Path;

use base64::Engine as _;

use crate::error::{Error, Result};

/// The budget's verdict for the banner.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BudgetBanner {
    /// The budget file, as given.
    pub file: String,
    /// One line per figure over budget ("pass '#0': samples passed 80000 > budget 72000 (+11.1%)").
    pub over: Vec<String>,
}

/// A table row; `over` marks a row over its budget.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Row {
    pub cells: Vec<String>,
    pub over: bool,
}

impl Row {
    pub fn new(cells: Vec<String>) -> Self {
        Row { cells, over: false }
    }
}

/// A finding of the tiler check: where, what, and one sentence of advice.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Finding {
    pub place: String,
    pub what: String,
    pub advice: String,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Section {
    /// SVG charts, side by side where they fit.
    Charts {
        title: String,
        svgs: Vec<String>,
    },
    Table {
        title: String,
        note: Option<String>,
        header: Vec<String>,
        rows: Vec<Row>,
    },
    Findings {
        title: String,
        note: Option<String>,
        findings: Vec<Finding>,
    },
    Image {
        title: String,
        caption: String,
        png: Vec<u8>,
    },
    Lines {
        title: String,
        lines: Vec<String>,
    },
}

/// A run's page.
#[derive(Debug, Clone, PartialEq)]
pub struct Page {
    /// e.g. "nostencil profile-app: vkcube".
    pub title: String,
    /// (what, value) under the banner: program, device, frame size, frames measured.
    pub facts: Vec<(String, String)>,
    /// None: no budget was checked (the banner then says `neutral`).
    pub budget: Option<BudgetBanner>,
    /// The banner's words when no budget was checked.
    pub neutral: String,
    pub sections: Vec<Section>,
    /// The run's report as `--format json` prints it, embedded for dashboards.
    pub json: String,
}

/// The id of the element that holds the embedded JSON.
pub const JSON_ID: &str = "nostencil-report";

/// `text` as HTML or XML text or attribute value (the JUnit XML uses it too): markup
/// characters as entities, control characters other than tab and newline as spaces (XML 1.0
/// allows none).
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\n' && c != '\t' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

const STYLE: &str = "\
body{font-family:'DejaVu Sans',Arial,sans-serif;margin:0;color:#1b1b1b;background:#fff}
main{max-width:1180px;margin:0 auto;padding:0 20px 40px}
h1{font-size:22px;margin:18px 0 8px}h2{font-size:17px;margin:26px 0 8px;border-bottom:1px solid #ddd;padding-bottom:4px}
.banner{padding:16px 20px;color:#fff;font-size:17px}
.banner.pass{background:#1e7d32}.banner.fail{background:#b3261e}.banner.none{background:#546e7a}
.banner ul{margin:6px 0 0;padding-left:22px;font-size:14px}
.facts{display:flex;flex-wrap:wrap;gap:6px 22px;font-size:14px;margin:6px 0}
.facts b{color:#555;font-weight:normal}
.charts{display:flex;flex-wrap:wrap;gap:14px}
.charts svg{border:1px solid #e3e3e3;max-width:100%;height:auto}
table{border-collapse:collapse;font-size:13px;margin:6px 0}
th,td{border:1px solid #d8d8d8;padding:3px 7px;text-align:right;vertical-align:top}
th{background:#f3f3f3}td:first-child,th:first-child{text-align:left}
tr.over td{background:#fde7e5}
.note{font-size:13px;color:#555;margin:4px 0}
.finding{margin:8px 0;font-size:14px}.finding .advice{color:#0b5394}
img.capture{border:1px solid #ccc;image-rendering:pixelated;max-width:100%}
pre{font-size:12px;background:#f6f6f6;padding:8px;white-space:pre-wrap}
td:last-child{text-align:left}
@media print{.banner{-webkit-print-color-adjust:exact;print-color-adjust:exact}.charts svg{break-inside:avoid}}
";

/// The JSON as the inside of a `<script type="application/json">`: `<` written `\u003c`, so
/// that no `</script>` can end it early; a JSON parser reads it back unchanged.
fn inert_json(json: &str) -> String {
    json.replace('<', "\\u003c")
}

impl Page {
    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = write!(
            out,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n",
            escape(&self.title)
        );
        match &self.budget {
            Some(b) if b.over.is_empty() => {
                let _ = writeln!(out, "<div class=\"banner pass\">Budget passed: within {}</div>", escape(&b.file));
            }
            Some(b) => {
                let _ = write!(
                    out,
                    "<div class=\"banner fail\">Budget failed: {} figure(s) over {}<ul>",
                    b.over.len(),
                    escape(&b.file)
                );
                for line in &b.over {
                    let _ = write!(out, "<li>{}</li>", escape(line));
                }
                out.push_str("</ul></div>\n");
            }
            None => {
                let _ = writeln!(out, "<div class=\"banner none\">{}</div>", escape(&self.neutral));
            }
        }
        let _ = write!(out, "<main>\n<h1>{}</h1>\n<div class=\"facts\">", escape(&self.title));
        for (what, value) in &self.facts {
            let _ = write!(out, "<span><b>{}</b> {}</span>", escape(what), escape(value));
        }
        out.push_str("</div>\n");
        for section in &self.sections {
            section.render(&mut out);
        }
        let _ = write!(
            out,
            "<h2>The report as JSON</h2>\n<p class=\"note\">Embedded in this page as <code>&lt;script type=\"application/json\" id=\"{JSON_ID}\"&gt;</code>, the same as <code>--format json</code>.</p>\n<script type=\"application/json\" id=\"{JSON_ID}\">{}</script>\n</main>\n</body>\n</html>\n",
            inert_json(&self.json)
        );
        out
    }

    /// Written whole to `path` (a temporary file renamed, like every output).
    pub fn write(&self, path: &Path) -> Result<()> {
        crate::frame::write_atomically(path, self.render().as_bytes())?;
        eprintln!("wrote {}", path.display());
        Ok(())
    }
}

impl Section {
    fn render(&self, out: &mut String) {
        match self {
            Section::Charts { title, svgs } => {
                let _ = write!(out, "<h2>{}</h2>\n<div class=\"charts\">", escape(title));
                for svg in svgs {
                    out.push_str(svg);
                }
                out.push_str("</div>\n");
            }
            Section::Table { title, note, header, rows } => {
                let _ = writeln!(out, "<h2>{}</h2>", escape(title));
                if let Some(note) = note {
                    let _ = writeln!(out, "<p class=\"note\">{}</p>", escape(note));
                }
                out.push_str("<table><tr>");
                for h in header {
                    let _ = write!(out, "<th>{}</th>", escape(h));
                }
                out.push_str("</tr>\n");
                for row in rows {
                    out.push_str(if row.over { "<tr class=\"over\">" } else { "<tr>" });
                    for cell in &row.cells {
                        let _ = write!(out, "<td>{}</td>", escape(cell));
                    }
                    out.push_str("</tr>\n");
                }
                out.push_str("</table>\n");
            }
            Section::Findings { title, note, findings } => {
                let _ = writeln!(out, "<h2>{}</h2>", escape(title));
                if let Some(note) = note {
                    let _ = writeln!(out, "<p class=\"note\">{}</p>", escape(note));
                }
                if findings.is_empty() {
                    out.push_str("<p>No finding.</p>\n");
                }
                for f in findings {
                    let _ = writeln!(
                        out,
                        "<div class=\"finding\"><b>{}</b>: {}<br><span class=\"advice\">{}</span></div>",
                        escape(&f.place),
                        escape(&f.what),
                        escape(&f.advice)
                    );
                }
            }
            Section::Image { title, caption, png } => {
                let data = base64::engine::general_purpose::STANDARD.encode(png);
                let _ = writeln!(
                    out,
                    "<h2>{}</h2>\n<img class=\"capture\" alt=\"{}\" src=\"data:image/png;base64,{data}\">\n<p class=\"note\">{}</p>",
                    escape(title),
                    escape(caption),
                    escape(caption)
                );
            }
            Section::Lines { title, lines } => {
                let _ = write!(out, "<h2>{}</h2>\n<pre>", escape(title));
                for line in lines {
                    let _ = writeln!(out, "{}", escape(line));
                }
                out.push_str("</pre>\n");
            }
        }
    }
}

/// The embedded JSON of a page written by `Page::render` (for the tests and dashboards that
/// read it back).
pub fn embedded_json(html: &str) -> Result<serde_json::Value> {
    let open = format!("<script type=\"application/json\" id=\"{JSON_ID}\">");
    let start = html.find(&open).ok_or_else(|| Error::InvalidInput("no embedded report in the page".into()))?;
    let rest = &html[start + open.len()..];
    let end = rest.find("</script>").ok_or_else(|| Error::InvalidInput("the embedded report never ends".into()))?;
    serde_json::from_str(&rest[..end]).map_err(|e| Error::InvalidInput(format!("the embedded report is not JSON: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn page(budget: Option<BudgetBanner>) -> Page {
        Page {
            title: "nostencil profile-app: <demo>".into(),
            facts: vec![("device".into(), "llvmpipe".into())],
            budget,
            neutral: "No budget checked".into(),
            sections: vec![Section::Table {
                title: "Render passes".into(),
                note: None,
                header: vec!["pass".into(), "draws".into()],
                rows: vec![Row { cells: vec!["#0".into(), "1".into()], over: true }],
            }],
            json: r#"{"label":"</script><b>"}"#.into(),
        }
    }

    #[test]
    fn the_page_escapes_text_and_embeds_the_json_unchanged() {
        let html = page(None).render();
        assert!(html.contains("&lt;demo&gt;") && !html.contains("<demo>"));
        assert_eq!(html.matches("</script>").count(), 1, "the JSON cannot close its element");
        let json = embedded_json(&html).expect("embedded");
        assert_eq!(json, serde_json::json!({"label": "</script><b>"}));
        assert!(html.contains("class=\"banner none\""));
    }

    #[test]
    fn a_failed_budget_names_every_figure_over_it() {
        let over = vec!["pass '#0': draws 2 > budget 1 (+100.0%)".to_owned()];
        let html = page(Some(BudgetBanner { file: "b.json".into(), over })).render();
        assert!(html.contains("class=\"banner fail\""));
        assert!(html.contains("pass &apos;#0&apos;: draws 2 &gt; budget 1"), "{html}");
        let passed = page(Some(BudgetBanner { file: "b.json".into(), over: Vec::new() })).render();
        assert!(passed.contains("class=\"banner pass\""));
    }
}
