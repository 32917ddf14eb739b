//! A budget's verdict as JUnit XML (`--junit FILE` beside `--budget`), the format GitLab's,
//! Jenkins' and GitHub's test reporters read: one test suite, one test case per budgeted pass
//! (and work row, and the frame's bytes), failed where any of its figures is over budget, with
//! every figure and its margin in the message.

use std::fmt::Write as _;
use std::path::Path;

use super::budget::BudgetFigure;
use super::html::page::escape;
use crate::error::Result;

/// The XML of `figures` (every figure the budget was compared on), as suite `suite`.
pub fn render(suite: &str, budget_file: &str, figures: &[BudgetFigure]) -> String {
    // The test cases, in the order their parts first appear.
    let mut parts: Vec<&str> = Vec::new();
    for f in figures {
        if !parts.contains(&f.pass.as_str()) {
            parts.push(&f.pass);
        }
    }
    let failed = |part: &str| figures.iter().any(|f| f.pass == part && f.over());
    let failures = parts.iter().filter(|p| failed(p)).count();
    let mut xml = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        xml,
        "<testsuites name=\"nostencil budget\" tests=\"{}\" failures=\"{failures}\" errors=\"0\" time=\"0\">",
        parts.len()
    );
    let _ = writeln!(
        xml,
        "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{failures}\" errors=\"0\" skipped=\"0\" time=\"0\">",
        escape(suite),
        parts.len()
    );
    let _ = writeln!(xml, "    <properties><property name=\"budget\" value=\"{}\"/></properties>", escape(budget_file));
    for part in parts {
        let mine: Vec<&BudgetFigure> = figures.iter().filter(|f| f.pass == part).collect();
        let _ = write!(xml, "    <testcase classname=\"{}\" name=\"{}\" time=\"0\"", escape(suite), escape(part));
        let lines: Vec<String> = mine.iter().map(|f| f.brief()).collect();
        if failed(part) {
            let over: Vec<String> = mine.iter().filter(|f| f.over()).map(|f| f.to_string()).collect();
            let _ = writeln!(
                xml,
                ">\n      <failure message=\"{}\" type=\"over budget\">{}</failure>\n    </testcase>",
                escape(&over.join("; ")),
                escape(&lines.join("\n"))
            );
        } else {
            let _ = writeln!(xml, ">\n      <system-out>{}</system-out>\n    </testcase>", escape(&lines.join("\n")));
        }
    }
    xml.push_str("  </testsuite>\n</testsuites>\n");
    xml
}

pub fn write(path: &Path, suite: &str, budget_file: &str, figures: &[BudgetFigure]) -> Result<()> {
    crate::frame::write_atomically(path, render(suite, budget_file, figures).as_bytes())?;
    eprintln!("wrote {}", path.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure(pass: &str, counter: &'static str, budget: u64, actual: u64) -> BudgetFigure {
        BudgetFigure { pass: pass.into(), counter, budget, actual }
    }

    #[test]
    fn a_case_per_pass_failed_where_a_figure_is_over_with_its_margin() {
        let figures = [
            figure("render pass #0", "draws", 1, 1),
            figure("render pass #0", "samples passed", 100, 150),
            figure("render pass #1 'a<b>'", "draws", 2, 2),
        ];
        let xml = render("vkcube", "budget.json", &figures);
        assert!(xml.contains("tests=\"2\" failures=\"1\""), "{xml}");
        assert_eq!(xml.matches("<testcase ").count(), 2);
        assert_eq!(xml.matches("<failure ").count(), 1);
        assert!(xml.contains("samples passed 150 &gt; budget 100 (+50.0%)"), "{xml}");
        assert!(xml.contains("name=\"render pass #1 &apos;a&lt;b&gt;&apos;\""), "{xml}");
    }
}
