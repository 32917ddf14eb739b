//! The Khronos glTF-Validator's test files (tests/gltf-validator, see its README) as a
//! conformance suite for the loader. Each file is classified by the validator's own expected
//! report (`numErrors == 0`: valid) and then:
//! - valid: must load; if it holds triangles it becomes a scene and one small frame is rendered
//!   under the validation layer; if it holds none, the scene builder must say exactly that;
//! - invalid: must be refused with one line naming the problem, unless it is listed in
//!   `ACCEPTED_INVALID` (a defect that does not matter to a renderer), where it must load;
//! - nothing may panic (every load is run under `catch_unwind`).
//!
//! Run with `--nocapture` to see the counts.

use crate::common;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use nostencil::scene::load_gltf;
use nostencil::scene_from_gltf;
use nostencil::Gpu;
use nostencil::{render_scene, RenderOptions};

#[path = "gltf_conformance/accepted.rs"]
mod accepted;

use accepted::ACCEPTED_INVALID;

/// Valid files (per the validator, which does not look for the data of a buffer without a
/// `uri`) whose triangles read such a buffer in a .gltf file: the data is not in the file, so the
/// loader reads zeros and must say so in a warning naming the buffer.
const VALID_WITHOUT_DATA: &[(&str, &str)] = &[
    ("base/data/root/named_objects.gltf", "buffer 0 has no uri"),
    ("base/data/root/unused_objects.gltf", "buffer 0 has no uri"),
];

const FRAME: u32 = 32;

fn suite_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/gltf-validator")
}

/// Every `*.report.json` under `dir`, sorted.
fn reports(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> =
        std::fs::read_dir(dir).expect("read suite dir").map(|e| e.expect("entry").path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            reports(&path, out);
        } else if path.to_string_lossy().ends_with(".report.json") {
            out.push(path);
        }
    }
}

struct Expected {
    errors: u64,
    /// Triangles the validator counts and a renderer must draw: none when every mesh is unused
    /// or a primitive lacks POSITION (the validator counts those triangles all the same).
    drawable: bool,
    /// The validator's first error code and pointer, to say what an invalid file is about.
    first_error: String,
}

fn expected(report: &Path) -> Expected {
    let text = std::fs::read_to_string(report).expect("read report");
    let json: serde_json::Value = serde_json::from_str(&text).expect("report is JSON");
    let issues = &json["issues"];
    let first_error = issues["messages"]
        .as_array()
        .into_iter()
        .flatten()
        .filter(|m| m["severity"] == 0)
        .map(|m| format!("{} at {}", m["code"].as_str().unwrap_or("?"), m["pointer"].as_str().unwrap_or("-")))
        .collect::<Vec<_>>()
        .join(", ");
    let messages: Vec<(&str, &str)> = issues["messages"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|m| (m["code"].as_str().unwrap_or_default(), m["pointer"].as_str().unwrap_or_default()))
        .collect();
    let unused_meshes = messages.iter().filter(|(c, p)| *c == "UNUSED_OBJECT" && p.starts_with("/meshes/")).count();
    let no_position = messages.iter().any(|(c, _)| *c == "MESH_PRIMITIVE_NO_POSITION");
    let triangles = json["info"]["totalTriangleCount"].as_u64().unwrap_or(0);
    Expected {
        errors: issues["numErrors"].as_u64().expect("numErrors"),
        drawable: triangles > 0 && unused_meshes == 0 && !no_position,
        first_error,
    }
}

#[derive(Default)]
struct Counts {
    valid_loaded: usize,
    valid_without_data: usize,
    /// Files (valid, or invalid and accepted) rendered, or loaded without triangles to render.
    rendered: usize,
    without_triangles: usize,
    invalid_refused: usize,
    invalid_accepted: usize,
    panics: usize,
    failures: Vec<String>,
}

fn panic_text(payload: &Box<dyn std::any::Any + Send>) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "non-string panic".into())
}

fn render(gpu: &Arc<Gpu>, path: &Path) -> Result<bool, String> {
    let scene = match std::panic::catch_unwind(|| scene_from_gltf(path, 0.0)) {
        Err(p) => return Err(format!("PANIC building the scene: {}", panic_text(&p))),
        Ok(Err(e)) if e.to_string().contains("no triangle meshes") => return Ok(false),
        Ok(Err(e)) => return Err(format!("loads but the scene fails: {e}")),
        Ok(Ok(scene)) => scene,
    };
    let options = RenderOptions { width: FRAME, height: FRAME, ..Default::default() };
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| render_scene(gpu, &scene, &options))) {
        Err(p) => Err(format!("PANIC rendering: {}", panic_text(&p))),
        Ok(Err(e)) => Err(format!("does not render: {e}")),
        Ok(Ok(_)) => Ok(true),
    }
}

/// Renders a file that loaded; a file the validator counts drawable triangles in must give a
/// frame, any other may instead say it has no triangle meshes.
fn render_and_count(gpu: &Arc<Gpu>, file: &Path, name: &str, drawable: bool, counts: &mut Counts) {
    match render(gpu, file) {
        Ok(true) => counts.rendered += 1,
        Ok(false) if !drawable => counts.without_triangles += 1,
        Ok(false) => counts.failures.push(format!("{name}: has drawable triangles, but the scene has none")),
        Err(e) => {
            counts.panics += e.starts_with("PANIC") as usize;
            counts.failures.push(format!("{name}: {e}"));
        }
    }
}

#[test]
fn validator_suite_loads_valid_files_and_refuses_invalid_ones() {
    let started = std::time::Instant::now();
    let gpu = common::gpu();
    let dir = suite_dir();
    let mut all = Vec::new();
    reports(&dir, &mut all);
    assert!(all.len() > 300, "only {} validator reports found under {}", all.len(), dir.display());
    let mut counts = Counts::default();
    for report in &all {
        let file = PathBuf::from(report.to_string_lossy().trim_end_matches(".report.json"));
        let name = file.strip_prefix(&dir).expect("under the suite").to_string_lossy().into_owned();
        let expected = expected(report);
        let loaded = std::panic::catch_unwind(|| load_gltf(&file));
        let loaded = match loaded {
            Ok(result) => result,
            Err(payload) => {
                counts.panics += 1;
                counts.failures.push(format!("{name}: PANIC {}", panic_text(&payload)));
                continue;
            }
        };
        let accepted = ACCEPTED_INVALID.iter().find(|(n, _)| *n == name);
        let without_data = VALID_WITHOUT_DATA.iter().find(|(n, _)| *n == name);
        match (expected.errors, loaded) {
            (0, Ok(model)) if without_data.is_some() => {
                if without_data.is_some_and(|(_, why)| model.warnings.iter().any(|w| w.contains(why))) {
                    counts.valid_without_data += 1;
                    counts.valid_loaded += 1;
                    render_and_count(&gpu, &file, &name, expected.drawable, &mut counts);
                } else {
                    counts.failures.push(format!("{name}: its missing buffer data is not warned of"))
                }
            }
            (0, Ok(_)) => {
                counts.valid_loaded += 1;
                render_and_count(&gpu, &file, &name, expected.drawable, &mut counts);
            }
            (0, Err(e)) => counts.failures.push(format!("{name}: valid but refused: {e}")),
            (_, Err(e)) => {
                let line = e.to_string();
                if line.contains('\n') || !line.starts_with(&format!("{}: ", file.display())) {
                    counts.failures.push(format!("{name}: refused, but not with one line naming the file: {line:?}"));
                } else if accepted.is_some() {
                    counts.failures.push(format!("{name}: listed as accepted but refused: {line}"));
                } else {
                    counts.invalid_refused += 1;
                }
            }
            (_, Ok(model)) => match accepted {
                Some(_) => {
                    counts.invalid_accepted += 1;
                    render_and_count(&gpu, &file, &name, false, &mut counts);
                }
                None => counts.failures.push(format!(
                    "{name}: invalid ({} errors: {}) but loaded; warnings {:?}",
                    expected.errors, expected.first_error, model.warnings
                )),
            },
        }
    }
    common::assert_no_validation_messages(&gpu);
    let elapsed = started.elapsed();
    println!(
        "glTF-Validator suite: {} files; valid: {} loaded ({} of them read a buffer with no data as zeros, warned); invalid: {} \
         refused, {} accepted as harmless (listed); of those loaded {} rendered a frame, {} have no triangles \
         to draw; panics {}; {:.1} s",
        all.len(),
        counts.valid_loaded,
        counts.valid_without_data,
        counts.invalid_refused,
        counts.invalid_accepted,
        counts.rendered,
        counts.without_triangles,
        counts.panics,
        elapsed.as_secs_f64()
    );
    for (listed, _) in ACCEPTED_INVALID.iter().chain(VALID_WITHOUT_DATA) {
        assert!(
            all.iter().any(|r| r.to_string_lossy().contains(listed)),
            "ACCEPTED_INVALID names {listed}, not in the suite"
        );
    }
    assert!(counts.failures.is_empty(), "{} file(s) misbehave:\n{}", counts.failures.len(), counts.failures.join("\n"));
    assert_eq!(counts.panics, 0);
}

/// Every real file of tests/assets (exported by Blender, gltfpack, FBX2glTF, COLLADA2GLTF)
/// loads and renders a frame under the validation layer, including BoxMeshopt.glb, which
/// requires EXT_meshopt_compression and whose fallback buffer has no data at all (loading it
/// would fail: it is never read).
#[test]
fn test_assets_load_and_render() {
    let gpu = common::gpu();
    let mut files = Vec::new();
    let mut stack = vec![common::test_assets()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("read assets") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "gltf" || e == "glb") {
                files.push(path);
            }
        }
    }
    files.sort();
    assert!(files.len() >= 15, "{} files", files.len());
    for file in &files {
        assert_eq!(render(&gpu, file), Ok(true), "{}", file.display());
    }
    common::assert_no_validation_messages(&gpu);
}
