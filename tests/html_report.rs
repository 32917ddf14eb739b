//! One HTML page per run (`--html`), opened in a real browser: Debian's Chromium, headless
//! (tools/setup-debian.sh installs it). The pages of `profile-app` on vkcube (64 frames), of
//! `profile` on nostencil's own default frame and of `bench` load with no console message, show
//! their charts, stay under 2 MB, and embed the JSON `--format json` writes, equal to it. A
//! budget recorded on one run and failed by a larger one gives a red banner naming what grew
//! (a passed one is green), and `--junit` writes the verdict as JUnit XML valid against the
//! schema in tests/assets/junit/.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::x_server::{start_x_server, XServer};
use nostencil::embedded_json;

/// Headless Chromium's screenshot of `page` (`height` pixels tall, 1280 wide) and what it
/// logged; fails the test on any console message.
fn open_in_chromium(page: &Path, height: u32) -> image::RgbaImage {
    let dir = page.with_extension("chromium");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("profile folder");
    let shot = page.with_extension("png");
    let output = Command::new("timeout")
        .arg("120")
        .arg("chromium")
        .args(["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run"])
        .args(["--disable-background-networking", "--disable-component-update", "--disable-sync"])
        .args(["--enable-logging=stderr", "--v=0", "--hide-scrollbars"])
        .arg(format!("--user-data-dir={}", dir.display()))
        .arg(format!("--window-size=1280,{height}"))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("chromium (tools/setup-debian.sh installs it)");
    let log = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "chromium failed on {}:\n{log}", page.display());
    let console: Vec<&str> = log.lines().filter(|l| l.contains("CONSOLE") || l.contains("Uncaught")).collect();
    assert!(console.is_empty(), "console messages on {}:\n{}", page.display(), console.join("\n"));
    image::open(&shot).unwrap_or_else(|e| panic!("{}: {e}", shot.display())).to_rgba8()
}

/// Whether the screenshot shows the charts' first colour (#4878d0) over many pixels.
fn shows_charts(shot: &image::RgbaImage) -> bool {
    shot.pixels().filter(|p| p[0] == 0x48 && p[1] == 0x78 && p[2] == 0xd0).count() > 2000
}

/// The banner's colour, from a pixel near the page's top left.
fn banner(shot: &image::RgbaImage) -> [u8; 3] {
    let p = shot.get_pixel(4, 4);
    [p[0], p[1], p[2]]
}

fn json_file(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).expect("JSON written")).expect("JSON")
}

fn page(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn arg(path: &Path) -> String {
    path.to_string_lossy().into_owned()
}

/// `profile-app EXTRA -- vkcube WIDTHxHEIGHT`, whatever its exit status.
fn vkcube(x: &XServer, extra: &[String], width: u32, height: u32) -> std::process::Output {
    let (w, h) = (width.to_string(), height.to_string());
    let mut args: Vec<&str> = vec!["profile-app"];
    args.extend(extra.iter().map(String::as_str));
    args.extend(["--", "vkcube", "--width", w.as_str(), "--height", h.as_str()]);
    common::nostencil_command(&args)
        .env("DISPLAY", &x.display)
        .env_remove("VK_INSTANCE_LAYERS")
        .output()
        .expect("profile-app runs")
}

#[test]
fn pages_of_vkcube_nostencils_frame_and_bench_load_in_chromium_and_embed_their_json() {
    let x = start_x_server();
    let dir = common::scratch_dir("html_report");
    let (html, json) = (dir.join("vkcube.html"), dir.join("vkcube.json"));
    let extra = ["--frames", "64", "--format", "json", "--out", &arg(&json), "--html", &arg(&html)].map(String::from);
    common::assert_success("profile-app --html -- vkcube", &vkcube(&x, &extra, 256, 256));
    let text = page(&html);
    assert!(text.len() <= 2 * 1024 * 1024, "{} bytes for 64 frames", text.len());
    assert_eq!(embedded_json(&text).expect("embedded"), json_file(&json), "the page's JSON is --format json's");
    // Self-contained: nothing fetched (the SVGs' namespace is a name, not a fetch).
    assert!(text.matches("<svg").count() >= 5, "the five charts");
    for fetch in ["<script src", "<link", "src=\"http", "href=", "url(", "@import"] {
        assert!(!text.contains(fetch), "the page fetches something: {fetch}");
    }
    let shot = open_in_chromium(&html, 1700);
    assert!(shows_charts(&shot), "the charts show");

    // nostencil's own frame: its page has the heat map and the technique's figures.
    let own = dir.join("own.html");
    let output = common::nostencil(&["profile", "--size", "160x96", "--format", "json", "--html", &arg(&own)]);
    let (stdout, _) = common::assert_success("profile --html", &output);
    let text = page(&own);
    let printed: serde_json::Value = serde_json::from_str(&stdout).expect("profile's JSON");
    assert_eq!(embedded_json(&text).expect("embedded"), printed);
    assert!(text.contains("Overdraw heat map") && text.contains("data:image/png;base64,"));
    assert!(text.contains("shadow-volume: its own figures"), "the technique's stats");
    assert!(shows_charts(&open_in_chromium(&own, 2400)));

    // bench: each variant's frame time, its interval and its ratio.
    let bench = dir.join("bench.html");
    let args = ["bench", "--technique", "lit", "--size", "64x48", "--warmup", "1", "--runs", "3", "--format", "json"];
    let output = common::nostencil(&[&args[..], &["--html", &arg(&bench)]].concat());
    let (stdout, _) = common::assert_success("bench --html", &output);
    let text = page(&bench);
    let printed: serde_json::Value = serde_json::from_str(&stdout).expect("bench's JSON");
    assert_eq!(embedded_json(&text).expect("embedded"), printed);
    assert!(text.contains("Ratio to the first") && text.contains("frame ratio"));
    assert!(shows_charts(&open_in_chromium(&bench, 1200)));
}

#[test]
fn a_failed_budget_turns_the_banner_red_names_what_grew_and_writes_junit() {
    let x = start_x_server();
    let dir = common::scratch_dir("html_report_budget");
    let budget = dir.join("budget.json");
    let record =
        ["--frames", "3", "--record-budget", &arg(&budget), "--out", &arg(&dir.join("r.txt"))].map(String::from);
    common::assert_success("record a budget", &vkcube(&x, &record, 200, 150));

    let check = |name: &str, width: u32| -> (std::process::Output, PathBuf, PathBuf) {
        let (html, junit) = (dir.join(format!("{name}.html")), dir.join(format!("{name}.xml")));
        let args = ["--frames", "3", "--budget", &arg(&budget), "--html", &arg(&html), "--junit", &arg(&junit)]
            .map(String::from);
        let mut extra = args.to_vec();
        extra.extend(["--out".to_owned(), arg(&dir.join(format!("{name}.txt")))]);
        (vkcube(&x, &extra, width, 150), html, junit)
    };
    let (passed, passed_html, passed_junit) = check("passed", 200);
    common::assert_success("the same size within its budget", &passed);
    let (failed, failed_html, failed_junit) = check("failed", 320);
    assert!(!failed.status.success(), "a larger window fails the budget");

    let text = page(&failed_html);
    assert!(text.contains("class=\"banner fail\"") && text.contains("Budget failed"), "the banner");
    assert!(text.contains("pass &apos;frame&apos;: tiler bytes per frame"), "the banner names what grew");
    assert!(page(&passed_html).contains("class=\"banner pass\""));
    let (red, green) = (banner(&open_in_chromium(&failed_html, 900)), banner(&open_in_chromium(&passed_html, 900)));
    assert!(red[0] > 150 && red[1] < 80 && red[2] < 80, "a failed budget's banner is red: {red:?}");
    assert!(green[1] > 100 && green[0] < 80 && green[2] < 100, "a passed one is green: {green:?}");

    let schema = common::test_asset("junit/junit.xsd");
    for (xml, failures) in [(&passed_junit, 0), (&failed_junit, 1)] {
        let output = Command::new("xmllint")
            .args(["--noout", "--schema"])
            .arg(&schema)
            .arg(xml)
            .output()
            .expect("xmllint (tools/setup-debian.sh installs libxml2-utils)");
        let said = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success() && said.contains("validates"), "{}: {said}", xml.display());
        let text = std::fs::read_to_string(xml).expect("JUnit written");
        assert_eq!(text.matches("<failure ").count(), failures, "{text}");
        assert!(text.contains("<testcase classname=\"vkcube\" name=\"render pass #0\""), "{text}");
    }
}
