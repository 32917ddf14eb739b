//! Meshes under a mirroring glTF node: the spec winds them clockwise, and the loader turns
//! their triangles so that every technique, which takes counter-clockwise fronts, draws them
//! facing out.

use std::path::Path;

use serde_json::json;

use crate::common;
use nostencil::scene::gltf::tests::{glb_parts, make_glb};
use nostencil::{render_scene, technique, CartoonOptions, OutlineMethod, RenderOptions, SilhouetteMethod};
use nostencil::{StencilMode, TECHNIQUES};

/// `tests/assets/Box.glb` is a unit cube centred on its node, so mirrored along x it is the same
/// solid: every technique (emulated and reference), and every silhouette and outline method,
/// draws it as the plain file, to a pixel or two of rounding. Before the turn, the scene passes drew its
/// inside, and the outline copy was pushed in (531 pixels of the outline differed).
#[test]
fn every_technique_draws_a_mirrored_box_as_the_plain_one() {
    let gpu = common::gpu();
    let bytes = std::fs::read(common::test_asset("Box.glb")).expect("Box.glb");
    let (mut json, bin) = glb_parts(&bytes);
    json["nodes"][1]["scale"] = json!([-1.0, 1.0, 1.0]);
    let mirrored_bytes = make_glb(&json, &bin);
    let load = |bytes: &[u8], name: &str| {
        let (scene, warnings) =
            nostencil::scene::scene_and_warnings_from_gltf_slice(bytes, Path::new(name), 0.0).expect("scene");
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
        scene
    };
    let (plain, mirrored) = (load(&bytes, "Box.glb"), load(&mirrored_bytes, "Mirrored.glb"));
    let box_object = |scene: &nostencil::Scene| scene.objects.iter().find(|o| o.casts_shadow).map(|o| o.transform);
    let determinant = box_object(&mirrored).expect("the box").determinant();
    assert!(determinant < 0.0, "the node mirrors: {determinant}");
    let base = RenderOptions { width: 96, height: 72, ..Default::default() };
    let mut cases: Vec<(String, RenderOptions)> =
        TECHNIQUES.iter().map(|t| (t.name().to_owned(), RenderOptions { technique: *t, ..base.clone() })).collect();
    for silhouette in [SilhouetteMethod::Shader, SilhouetteMethod::Hull, SilhouetteMethod::Extrusion] {
        let cartoon = CartoonOptions { silhouette, ..Default::default() };
        let options = RenderOptions { technique: technique("toon").expect("toon"), cartoon, ..base.clone() };
        cases.push((format!("toon {silhouette:?}"), options));
    }
    let cartoon = CartoonOptions { outline_method: OutlineMethod::Scale, ..Default::default() };
    let outline = RenderOptions { technique: technique("outline").expect("outline"), cartoon, ..base.clone() };
    cases.push(("outline scale".into(), outline));
    for (name, options) in cases {
        for stencil in [StencilMode::Emulated, StencilMode::Reference] {
            let options = RenderOptions { stencil, ..options.clone() };
            let a = render_scene(&gpu, &plain, &options).expect("plain").output.image;
            let b = render_scene(&gpu, &mirrored, &options).expect("mirrored").output.image;
            let differing = a.pixels().zip(b.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count();
            println!("{name} {stencil:?}: {differing} pixels differ");
            // A triangle listed in another corner order interpolates its N.V rim to another
            // rounding at a pixel or two; a box drawn inside out differs at hundreds.
            assert!(differing <= 4, "{name} {stencil:?}: the mirrored box differs at {differing} pixels");
        }
    }
    common::assert_no_validation_messages(&gpu);
}
