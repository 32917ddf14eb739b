//! The page's charts, as inline SVG: one bar per frame (or per pass), its series stacked (the
//! render passes of a frame, then its compute and transfer rows), with a legend and a scale.

use std::fmt::Write as _;

use super::page::escape;

/// Colours of the stacked series, in order (then again).
const PALETTE: [&str; 10] =
    ["#4878d0", "#ee854a", "#6acc64", "#d65f5f", "#956cb4", "#8c613c", "#dc7ec0", "#797979", "#d5bb67", "#82c6e2"];

/// One stacked series: its name and its value at each bar (0 where it has none).
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub name: String,
    pub values: Vec<f64>,
}

/// `value` written for a person: 1234567 as "1.23M", 0.5 as "0.5".
pub fn short(value: f64) -> String {
    let a = value.abs();
    if a >= 1e9 {
        format!("{:.2}G", value / 1e9)
    } else if a >= 1e6 {
        format!("{:.2}M", value / 1e6)
    } else if a >= 1e4 {
        format!("{:.1}k", value / 1e3)
    } else if a >= 100.0 || value == value.trunc() {
        format!("{value:.0}")
    } else {
        format!("{value:.3}")
    }
}

/// A stacked bar chart of `series` over the bars named by `bars` (frames or passes), `unit`
/// under its title.
pub fn stacked_bars(title: &str, unit: &str, bars: &[String], series: &[Series]) -> String {
    let (left, top, plot_w, plot_h, legend_row) = (64.0, 46.0, 460.0, 170.0, 16.0);
    let shown: Vec<&Series> = series.iter().filter(|s| s.values.iter().any(|v| *v > 0.0)).collect();
    let legend_rows = shown.len().div_ceil(2) as f64;
    let width = left + plot_w + 20.0;
    let height = top + plot_h + 34.0 + legend_rows * legend_row + 8.0;
    let totals: Vec<f64> =
        (0..bars.len()).map(|i| shown.iter().map(|s| s.values.get(i).copied().unwrap_or(0.0).max(0.0)).sum()).collect();
    let max = totals.iter().copied().fold(0.0f64, f64::max);
    let scale = if max > 0.0 { plot_h / max } else { 0.0 };
    let mut svg = String::new();
    let _ = write!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="DejaVu Sans, Arial, sans-serif" font-size="11"><rect width="100%" height="100%" fill="white"/>"#
    );
    let _ = write!(svg, r#"<text x="8" y="18" font-size="14" font-weight="bold">{}</text>"#, escape(title));
    let _ = write!(svg, r##"<text x="8" y="34" fill="#555">{}</text>"##, escape(unit));
    // Scale: 0 and the tallest bar.
    let base = top + plot_h;
    let _ = write!(
        svg,
        r##"<line x1="{left}" y1="{base}" x2="{}" y2="{base}" stroke="#999"/><line x1="{left}" y1="{top}" x2="{left}" y2="{base}" stroke="#999"/><text x="{}" y="{}" text-anchor="end">{}</text><text x="{}" y="{base}" text-anchor="end">0</text>"##,
        left + plot_w,
        left - 4.0,
        top + 4.0,
        escape(&short(max)),
        left - 4.0
    );
    let slot = if bars.is_empty() { plot_w } else { plot_w / bars.len() as f64 };
    let bar_w = (slot * 0.8).max(1.0);
    for (i, name) in bars.iter().enumerate() {
        let x = left + i as f64 * slot + (slot - bar_w) / 2.0;
        let mut y = base;
        for (k, s) in shown.iter().enumerate() {
            let v = s.values.get(i).copied().unwrap_or(0.0).max(0.0);
            if v <= 0.0 {
                continue;
            }
            let h = v * scale;
            y -= h;
            let _ = write!(
                svg,
                r#"<rect x="{x:.1}" y="{y:.1}" width="{bar_w:.1}" height="{h:.1}" fill="{}"><title>{}: {}: {}</title></rect>"#,
                PALETTE[k % PALETTE.len()],
                escape(name),
                escape(&s.name),
                escape(&short(v))
            );
        }
        // A label under every bar when they fit, else under the first and last.
        if bars.len() <= 16 || i == 0 || i + 1 == bars.len() {
            let _ = write!(
                svg,
                r#"<text x="{:.1}" y="{}" text-anchor="middle">{}</text>"#,
                x + bar_w / 2.0,
                base + 14.0,
                escape(name)
            );
        }
    }
    for (k, s) in shown.iter().enumerate() {
        let (col, row) = (k % 2, k / 2);
        let x = 8.0 + col as f64 * (width / 2.0);
        let y = base + 30.0 + row as f64 * legend_row;
        let _ = write!(
            svg,
            r#"<rect x="{x}" y="{}" width="10" height="10" fill="{}"/><text x="{}" y="{y}">{}</text>"#,
            y - 9.0,
            PALETTE[k % PALETTE.len()],
            x + 14.0,
            escape(&s.name)
        );
    }
    if shown.is_empty() {
        let _ = write!(svg, r##"<text x="{}" y="{}" fill="#777">nothing measured</text>"##, left + 10.0, top + 20.0);
    }
    svg.push_str("</svg>");
    svg
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_stack_their_series_and_the_tallest_sets_the_scale() {
        let bars = vec!["0".to_owned(), "1".to_owned()];
        let series = vec![
            Series { name: "#0".into(), values: vec![1.0, 2.0] },
            Series { name: "#1 <frame>".into(), values: vec![1.0, 0.0] },
            Series { name: "empty".into(), values: vec![0.0, 0.0] },
        ];
        let svg = stacked_bars("GPU time", "ms", &bars, &series);
        assert!(svg.starts_with("<svg") && svg.ends_with("</svg>"));
        assert_eq!(svg.matches("<rect x=").count(), 3 + 2, "three bar pieces and two legend keys");
        assert!(svg.contains("#1 &lt;frame&gt;") && !svg.contains("empty"), "{svg}");
        assert!(svg.contains(">2</text>"), "the scale's top is the tallest bar: {svg}");
    }

    #[test]
    fn short_numbers_read_at_a_glance() {
        assert_eq!(short(1_234_567.0), "1.23M");
        assert_eq!(short(12_345.0), "12.3k");
        assert_eq!(short(42.0), "42");
        assert_eq!(short(0.25), "0.250");
    }
}
