//! The cartoon techniques from the command line: each renders and profiles, and bad cartoon
//! options get a one-line error naming the option.

use crate::common;

use nostencil::builtin_scene;
use nostencil::CartoonOptions;

/// Ink: the edge methods' (10, 10, 15) and the shader method's darkened rim alike.
/// Within 25 of the ink colour as the sRGB frame stores it.
fn is_ink(p: &[u8; 3]) -> bool {
    let ink = common::srgb8(nostencil::technique::ink::renderer::INK_COLOUR.truncate());
    (0..3).all(|c| p[c] <= ink[c].saturating_add(25))
}

#[test]
fn every_cartoon_technique_and_method_renders_and_profiles() {
    let dir = common::scratch_dir("cartoon-cli");
    let cases: [&[&str]; 6] = [
        &["--scene", "outline", "--technique", "outline", "--select", "box,sphere"],
        &["--scene", "outline", "--technique", "outline", "--stencil", "reference"],
        &["--scene", "outline", "--technique", "silhouette", "--line-width", "3", "--crease-angle", "30"],
        &["--scene", "duck", "--technique", "toon", "--silhouette", "shader"],
        &["--scene", "default", "--technique", "toon", "--silhouette", "hull"],
        &["--scene", "duck", "--technique", "silhouette", "--silhouette", "edges"],
    ];
    let outline = CartoonOptions::default().outline_colour;
    for (i, extra) in cases.iter().enumerate() {
        let out = dir.join(format!("{i}.png"));
        let mut args = vec!["render", "--size", "96x64", "--validation", "--out"];
        args.push(out.to_str().expect("utf-8 path"));
        args.extend_from_slice(extra);
        let (_, err) = common::run_ok(&args);
        assert!(!err.contains("validation"), "{extra:?}: {err}");
        let image = common::read_png(&out);
        assert_eq!(image.dimensions(), (96, 64));
        // The scene's sky in the top corners; the outline's colour, or ink, drawn.
        let (scene, technique) = (extra[1], extra[3]);
        let sky = common::srgb8(builtin_scene(scene).expect("scene").background);
        assert_eq!((image.get_pixel(0, 0).0, image.get_pixel(95, 0).0), (sky, sky), "{extra:?}: top corners");
        if technique == "outline" {
            let outlined = image.pixels().filter(|p| p.0 == outline).count();
            assert!(outlined > 50, "{extra:?}: {outlined} pixels of the outline colour {outline:?}");
        } else {
            let inked = image.pixels().filter(|p| is_ink(&p.0)).count();
            assert!(inked > 50, "{extra:?}: {inked} ink pixels");
        }

        let mut args = vec!["profile", "--size", "96x64", "--format", "json"];
        args.extend_from_slice(extra);
        let (stdout, _) = common::run_ok(&args);
        let json: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
        assert!(json["passes"].as_array().is_some_and(|p| !p.is_empty()), "{extra:?}");
    }
}

#[test]
fn bad_cartoon_options_are_one_line_errors() {
    for (args, mentions) in [
        (&["--technique", "toon", "--silhouette", "sketch"][..], "--silhouette"),
        (&["--technique", "outline", "--select", "teapot"][..], "teapot"),
        (&["--technique", "silhouette", "--line-width", "0"][..], "--line-width"),
        (&["--technique", "silhouette", "--crease-angle", "500"][..], "--crease-angle"),
    ] {
        let mut all = vec!["profile", "--size", "32x32", "--scene", "outline"];
        all.extend_from_slice(args);
        let err = common::run_err(&all);
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(mentions), "'{mentions}' not in {err}");
    }
}
