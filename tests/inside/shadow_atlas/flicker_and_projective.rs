//! Mip flicker counted for both techniques, and the projective texture beside the atlas on a
//! concave model.

use super::*;

#[test]
fn mip_flicker_counts_flickering_pixels_of_both_techniques() {
    // atlas-one minified to 96x72: the model covers a few hundred pixels and its 256x256 shadow
    // texture is sampled around mip 3, where the map's compare still snaps per pixel.
    let args =
        "bench --technique shadow-texture-atlas --scene atlas-one --size 96x72 --mip-flicker 12 --json --validation";
    let (out, err) = common::run_ok(&args.split(' ').collect::<Vec<_>>());
    assert!(!err.contains("vulkan validation"), "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).expect("--mip-flicker --json is JSON");
    assert_eq!(report["schema"], "nostencil-mip-flicker/1");
    assert_eq!((report["steps"].as_u64(), report["width"].as_u64()), (Some(12), Some(96)), "{report}");
    let rows = report["rows"].as_array().expect("rows");
    let techniques: Vec<&str> = rows.iter().filter_map(|r| r["technique"].as_str()).collect();
    assert_eq!(techniques, ["atlas", "map"], "{report}");
    let count = |row: &serde_json::Value, key: &str| row[key].as_u64().expect(key);
    for row in rows {
        let (pixels, events) = (count(row, "flickering_pixels"), count(row, "flicker_events"));
        assert!(pixels <= 96 * 72 && pixels <= events && events <= 12 * pixels, "{row}");
        assert!(row["mean_change"].as_f64().is_some_and(|m| m > 0.0 && m < 32.0), "{row}");
    }
    let (atlas, map) = (count(&rows[0], "flickering_pixels"), count(&rows[1], "flickering_pixels"));
    println!("flickering pixels at 96x72 over 12 steps: shadow texture {atlas}, shadow map {map}");
    // The shadow map's edge snaps from pixel to pixel as the light turns: it must flicker
    // somewhere, or the measurement measures nothing.
    assert!(map >= 20, "{report}");
    // The paper's claim, which holds by a wide margin at this size (0 against 109 on lavapipe).
    assert!(atlas * 4 < map, "mips did not reduce the flicker: {atlas} against {map}");

    let refused = common::run_err(&["bench", "--technique", "planar", "--mip-flicker"]);
    assert!(refused.contains("--mip-flicker") && refused.contains("planar"), "{refused}");
    let refused = common::run_err(&["bench", "--mip-flicker", "--each-extrusion"]);
    assert!(refused.contains("--mip-flicker is not timed") && refused.contains("--each-extrusion"), "{refused}");
}

#[test]
fn projective_texture_shadows_lit_parts_of_a_concave_model_that_the_atlas_leaves_lit() {
    // The paper's figure 2: a texel of a texture projected from the light stands for every
    // surface on its light ray, so the lit horn in front of the body's self-shadow takes it.
    let gpu = common::gpu();
    let scene = builtin_scene("atlas-one").expect("scene");
    let (w, h) = (160u32, 120u32);
    let projective = render(&gpu, &scene, technique("projective-texture"), (w, h));
    let atlas = render(&gpu, &scene, technique("shadow-texture-atlas"), (w, h));
    let dir = common::scratch_dir("projective-vs-atlas");
    for (image, name) in [(&projective, "projective-texture"), (&atlas, "atlas")] {
        nostencil::write_png(image, &dir.join(format!("{name}.png")), false).expect("write png");
    }
    // Pixels the projective texture leaves clearly darker than the atlas.
    let darker: Vec<(u32, u32)> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (p, a) = (projective.get_pixel(x, y).0, atlas.get_pixel(x, y).0);
            (0..3).all(|c| a[c] >= p[c]) && (0..3).any(|c| a[c] > p[c].saturating_add(24))
        })
        .collect();

    // CPU answer for a pixel: the nearest surface on its camera ray and whether a ray from
    // there reaches the light (None: not a light-facing point of the model).
    let Light::Directional { direction } = scene.light() else { panic!("atlas-one has a directional light") };
    let to_light = -direction.normalize();
    let triangles = world_triangles(&scene);
    let model = scene.objects.iter().position(|o| o.name == "model").expect("the model");
    let inverse = scene.camera.view_projection(w as f32 / h as f32).inverse();
    let lit_model_point = |x: u32, y: u32| -> Option<bool> {
        let ndc = Vec2::new((x as f32 + 0.5) / w as f32 * 2.0 - 1.0, (y as f32 + 0.5) / h as f32 * 2.0 - 1.0);
        let eye = scene.camera.eye;
        let ray = (inverse.project_point3(ndc.extend(0.5)) - eye).normalize();
        let (object, t, d) = triangles
            .iter()
            .filter_map(|(i, t)| ray_hits_triangle(eye, ray, *t).map(|d| (*i, *t, d)))
            .min_by(|a, b| a.2.total_cmp(&b.2))?;
        let mut n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
        if n.dot(ray) > 0.0 {
            n = -n;
        }
        if object != model || n.dot(to_light) < 0.3 {
            return None;
        }
        let origin = eye + ray * d + n * 0.01;
        Some(!triangles.iter().any(|(_, t)| ray_hits_triangle(origin, to_light, *t).is_some_and(|d| d > 1e-4)))
    };
    let sampled: Vec<(u32, u32)> = darker.iter().step_by((darker.len() / 60).max(1)).copied().collect();
    let answers: Vec<Option<bool>> = sampled.iter().map(|&(x, y)| lit_model_point(x, y)).collect();
    let lit = answers.iter().filter(|a| **a == Some(true)).count();
    let occluded = answers.iter().filter(|a| **a == Some(false)).count();
    println!(
        "{} pixels darker under the projective texture than the atlas; of {} sampled, {lit} are light-facing \
         points of the model that a ray cast finds lit, {occluded} in shadow",
        darker.len(),
        sampled.len()
    );
    assert!(darker.len() >= 40, "the projective texture must show its flaw: {} pixels", darker.len());
    assert!(lit * 2 >= sampled.len(), "{lit} of {} sampled pixels are lit model surface", sampled.len());
    assert!(occluded * 10 <= sampled.len(), "{occluded} of them are really in shadow");
    common::assert_no_validation_messages(&gpu);
}
