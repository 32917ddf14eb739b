//! A per-pass bar chart as SVG: for each pass, fragments per pixel (fragment shader
//! invocations) and samples per pixel (samples passed) side by side, and its GPU time.

use std::fmt::Write as _;

use crate::render::FrameCounters;

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// One bar pair of the chart.
#[derive(Debug, Clone, PartialEq)]
pub struct ChartRow {
    pub name: String,
    /// Fragment shader invocations per pixel (0 where unknown).
    pub fragments_per_pixel: f64,
    /// Samples passed per pixel and sample.
    pub samples_per_pixel: f64,
    pub gpu_ms: f64,
}

/// The chart of a frame of this crate: one row per measured pass.
pub fn bar_chart_svg(title: &str, counters: &FrameCounters) -> String {
    let pixels = counters.pixels().max(1) as f64;
    let rows: Vec<ChartRow> = counters
        .passes
        .iter()
        .map(|p| ChartRow {
            name: p.name.clone(),
            fragments_per_pixel: p.fragment_invocations.map_or(0.0, |f| f as f64 / pixels),
            samples_per_pixel: counters.samples_per_pixel(p),
            gpu_ms: p.gpu_ms,
        })
        .collect();
    chart_rows_svg(title, &rows)
}

/// The chart of any rows (an application's render passes, measured by the fill-rate layer).
pub fn chart_rows_svg(title: &str, rows: &[ChartRow]) -> String {
    let rows: Vec<(String, f64, f64, f64)> =
        rows.iter().map(|r| (r.name.clone(), r.fragments_per_pixel, r.samples_per_pixel, r.gpu_ms)).collect();
    let max = rows.iter().map(|r| r.1.max(r.2)).fold(0.0f64, f64::max).max(1.0).ceil();
    let (label_w, bar_w, row_h, top) = (230.0, 460.0, 34.0, 70.0);
    let width = label_w + bar_w + 190.0;
    let height = top + rows.len() as f64 * row_h + 60.0;
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="DejaVu Sans, Arial, sans-serif" font-size="13">"#
    );
    let _ = writeln!(svg, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(svg, r#"<text x="12" y="24" font-size="16" font-weight="bold">{}</text>"#, escape(title));
    let _ = writeln!(
        svg,
        r##"<rect x="{label_w}" y="36" width="12" height="12" fill="#4878d0"/><text x="{}" y="47">fragment shader invocations / pixel</text><rect x="{}" y="36" width="12" height="12" fill="#ee854a"/><text x="{}" y="47">samples passed / (pixel x samples)</text>"##,
        label_w + 18.0,
        label_w + 270.0,
        label_w + 288.0
    );
    // Grid lines at whole full-screen passes.
    let step = (max / 8.0).ceil().max(1.0);
    let mut tick = 0.0;
    while tick <= max {
        let x = label_w + tick / max * bar_w;
        let _ = writeln!(
            svg,
            r##"<line x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#ddd"/><text x="{x}" y="{}" text-anchor="middle" fill="#555">{tick}</text>"##,
            top - 8.0,
            top + rows.len() as f64 * row_h,
            top + rows.len() as f64 * row_h + 16.0
        );
        tick += step;
    }
    let _ = writeln!(
        svg,
        r##"<text x="{}" y="{}" text-anchor="middle" fill="#555">full-screen passes (per pixel)</text>"##,
        label_w + bar_w / 2.0,
        top + rows.len() as f64 * row_h + 36.0
    );
    for (i, (name, fragments, samples, ms)) in rows.iter().enumerate() {
        let y = top + i as f64 * row_h;
        let _ =
            writeln!(svg, r#"<text x="{}" y="{}" text-anchor="end">{}</text>"#, label_w - 8.0, y + 18.0, escape(name));
        let _ = writeln!(
            svg,
            r##"<rect x="{label_w}" y="{}" width="{:.1}" height="11" fill="#4878d0"><title>{fragments:.3}</title></rect>"##,
            y + 4.0,
            fragments / max * bar_w
        );
        let _ = writeln!(
            svg,
            r##"<rect x="{label_w}" y="{}" width="{:.1}" height="11" fill="#ee854a"><title>{samples:.3}</title></rect>"##,
            y + 16.0,
            samples / max * bar_w
        );
        let _ = writeln!(
            svg,
            r##"<text x="{}" y="{}" fill="#333">{fragments:.2} / {samples:.2} · {ms:.2} ms</text>"##,
            label_w + (fragments.max(*samples) / max * bar_w) + 6.0,
            y + 20.0
        );
    }
    svg.push_str("</svg>\n");
    svg
}
