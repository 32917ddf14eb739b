//! `nostencil bake` writes a model's shadow texture from the command line, and Table 1 is
//! recorded beside the paper's values.

use super::*;

#[test]
fn bake_writes_the_models_shadow_texture_from_the_command_line() {
    let dir = common::scratch_dir("bake-cli");
    let out = dir.join("model.png");
    let (_, err) = common::run_ok(&["bake", "--scene", "atlas-one", "--out", out.to_str().unwrap()]);
    assert!(err.contains("of 'model'") && err.contains("geometry image 257x257"), "{err}");
    // The horned sphere shadows itself: its texture holds lit and shadowed texels.
    let texture = common::read_png(&out);
    assert_eq!(texture.dimensions(), (256, 256));
    let lit = texture.pixels().filter(|p| p[0] == 255).count();
    let shadowed = texture.pixels().filter(|p| p[0] == 0).count();
    assert!(lit > 256 * 256 / 10 && shadowed > 256 * 256 / 10, "{lit} lit, {shadowed} shadowed texels");

    let mip = dir.join("mip2.png");
    common::run_ok(&[
        "bake",
        "--scene",
        "atlas-one",
        "--model",
        "ground",
        "--mip",
        "2",
        "--out",
        mip.to_str().unwrap(),
    ]);
    let ground = common::read_png(&mip);
    assert_eq!(ground.dimensions(), (64, 64));
    // The ground is lit, but for the model's shadow on it.
    let lit = ground.pixels().filter(|p| p[0] == 255).count();
    let shadowed = ground.pixels().filter(|p| p[0] == 0).count();
    assert!(lit > 64 * 64 / 2 && shadowed > 20, "{lit} lit, {shadowed} shadowed texels at mip 2");

    let missing = dir.join("none.png");
    let err =
        common::run_err(&["bake", "--scene", "atlas-one", "--model", "teapot", "--out", missing.to_str().unwrap()]);
    assert!(err.contains("no model 'teapot'") && err.contains("ground, model"), "{err}");
    assert!(!missing.exists());

    // 400 separate triangles cannot be laid out in a 16x16 texture: the error follows the
    // progress line on a line of its own, and no file is written.
    let mut positions = Vec::new();
    for i in 0..400u32 {
        let (x, z) = ((i % 20) as f32 * 2.0, (i / 20) as f32 * 2.0);
        for p in [[x, 1.0, z], [x, 1.0, z + 1.0], [x + 1.0, 1.0, z]] {
            positions.extend(p.iter().flat_map(|c: &f32| c.to_le_bytes()));
        }
    }
    std::fs::write(dir.join("confetti.bin"), &positions).expect("write bin");
    let gltf = serde_json::json!({
        "asset": { "version": "2.0" },
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
        "buffers": [{ "uri": "confetti.bin", "byteLength": positions.len() }],
        "bufferViews": [{ "buffer": 0, "byteLength": positions.len() }],
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 1200, "type": "VEC3",
            "min": [0.0, 1.0, 0.0], "max": [39.0, 1.0, 39.0] }]
    });
    let scene = dir.join("confetti.gltf");
    std::fs::write(&scene, serde_json::to_vec(&gltf).expect("json")).expect("write gltf");
    let out = dir.join("confetti.png");
    let err = common::run_err(&[
        "bake",
        "--scene",
        scene.to_str().unwrap(),
        "--shadow-texture-size",
        "16",
        "--out",
        out.to_str().unwrap(),
    ]);
    let last = err.trim_end().lines().last().unwrap_or_default();
    assert!(last.starts_with("nostencil: error:") && last.contains("400 atlas charts do not fit"), "{err:?}");
    assert!(!out.exists());
}

#[test]
fn table1_is_recorded_beside_the_papers_values() {
    let dir = common::scratch_dir("table1");
    let out = dir.join("recorded");
    let args = ["bench", "--technique", "shadow-texture-atlas", "--size", "48x48", "--warmup", "1", "--runs", "3"];
    // No --validation: its per-call cost lands on both lights and blurs the timing this test
    // compares; the same frames run under validation in the other atlas tests.
    let (text, _) = common::run_ok(&[&args[..], &["--table1-out", out.to_str().unwrap()]].concat());
    assert!(text.contains("paper fps"), "{text}");

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("table1.json")).expect("table1.json")).expect("JSON");
    assert_eq!(json["schema"], "nostencil-table1/3");
    assert_eq!((json["width"].as_u64(), json["runs"].as_u64()), (Some(48), Some(3)));
    let rows = json["rows"].as_array().expect("rows");
    // Two scenes x two techniques x two lights, each with the paper's value beside it.
    assert_eq!(rows.len(), 8, "{json}");
    let paper = shadow_atlas_paper_values();
    for row in rows {
        for column in ["scene", "technique", "light", "fps", "frame_ms", "gpu_ms", "passes", "paper_fps"] {
            assert!(!row[column].is_null(), "row without {column}: {row}");
        }
        assert_eq!(row["frame_ms_rounds"].as_array().map(Vec::len), Some(3), "{row}");
        let key = (row["scene"].as_str().unwrap_or(""), row["technique"].as_str().unwrap_or(""));
        let light = row["light"].as_str().unwrap_or("");
        let (_, _, moving, fixed) = paper.iter().find(|p| (p.0, p.1.as_str()) == key).expect("a paper row");
        let expected = if light == "fixed" { *fixed } else { *moving };
        assert_eq!(row["paper_fps"].as_f64(), Some(expected), "{row}");
    }
    let markdown = std::fs::read_to_string(out.join("table1.md")).expect("table1.md");
    for (_, _, moving, fixed) in &paper {
        for value in [moving, fixed] {
            assert!(markdown.contains(&format!("{value:.2}")), "paper value {value} missing:\n{markdown}");
        }
    }
    assert_eq!(markdown.lines().filter(|l| l.starts_with("| atlas-")).count(), 8 + 8, "{markdown}");

    // A fixed light skips the shadow map (and bake): faster than a moving one, per round of the
    // same run, for both techniques on both scenes.
    let ratios = json["ratios"].as_array().expect("ratios");
    assert_eq!(ratios.len(), 8, "{json}");
    let fixed_over_moving: Vec<_> =
        ratios.iter().filter(|r| r["compared"].as_str().is_some_and(|c| c.contains("fixed / moving"))).collect();
    assert_eq!(fixed_over_moving.len(), 4, "{json}");
    for ratio in fixed_over_moving {
        let measured = ratio["measured"]["median"].as_f64().expect("measured ratio");
        println!("{} {}: {measured:.2} (paper {})", ratio["scene"], ratio["compared"], ratio["paper"]);
        assert!(measured > 1.0, "fixed light not faster than moving: {ratio}");
    }
    let refused = common::run_err(&["bench", "--technique", "planar", "--table1-out", out.to_str().unwrap()]);
    assert!(refused.contains("--table1-out") && refused.contains("planar"), "{refused}");
}

/// The paper's Table 1 as (scene, technique as JSON spells it, moving light fps, fixed light fps).
fn shadow_atlas_paper_values() -> Vec<(&'static str, String, f64, f64)> {
    let spelt = |k: &ShadowKind| serde_json::to_value(k).ok().and_then(|v| v.as_str().map(str::to_owned));
    nostencil::profile::table1::PAPER_TABLE1
        .iter()
        .map(|(s, k, m, f)| (*s, spelt(k).expect("technique as JSON"), *m, *f))
        .collect()
}
