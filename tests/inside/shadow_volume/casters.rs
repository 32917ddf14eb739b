//! What a caster casts, against answers computed on the CPU: a box's projected outline, open,
//! mirrored and inside-out casters, a camera inside a volume, the background, a point light's
//! ray cast; and how each caster's path is reported and named (warnings, `profile`, the CLI).

use super::*;

/// Intersection over union of the ground pixels the shadow darkened and those inside the
/// casters' projected outline, computed here on the CPU: the union of every casting triangle
/// projected along the light onto the ground (exact for any mesh, open or not). Pixels where
/// the lit frame shows a caster itself are left out: its unlit side is in its own volume but is
/// not ground. The shadow must cover more than 200 pixels.
fn projected_outline_iou(gpu: &Arc<Gpu>, scene: &Scene, options: ShadowVolumeOptions) -> f64 {
    const BIG: (u32, u32) = (256, 192);
    let triangles = common::caster_triangles_on_ground(scene);
    assert!(!triangles.is_empty(), "{}: no caster", scene.name);
    let unshadowed = lit_sized(gpu, scene, BIG);
    let frame = render_sized(gpu, scene, StencilMode::Emulated, options, BIG);
    let mask = shadow_mask(&frame.output.image, &unshadowed);
    let mut without = scene.clone();
    without.objects.retain(|o| !o.casts_shadow);
    let background = lit_sized(gpu, &without, BIG);
    let caster_pixels = common::differing_pixels(&unshadowed, &background);
    let (both, either) = common::outline_overlap(&scene.camera, BIG, &triangles, &caster_pixels, |i| mask[i]);
    assert!(either > 200, "{}: the shadow is too small to judge ({either} pixels)", scene.name);
    both as f64 / either as f64
}

#[test]
fn box_shadow_matches_its_projected_outline() {
    let gpu = common::gpu();
    let scene = builtin_scene("box").expect("scene");
    for &normalize in Normalize::ALL {
        let iou = projected_outline_iou(&gpu, &scene, ShadowVolumeOptions { normalize, ..seed() });
        assert!(iou > 0.99, "{}: intersection over union {iou:.4}", normalize.name());
    }
    common::assert_no_validation_messages(&gpu);
}

/// docs/design/any-mesh-volumes.md: a one-sided quad whose back faces the light, a box without its top seen
/// through the hole (the ground under it shows through its culled floor), a non-manifold fan
/// with a box wound inconsistently, and boxes touching along an edge cast their projected
/// outlines in z-pass and in z-fail.
#[test]
fn open_casters_shadow_their_projected_outline_in_zpass_and_zfail() {
    let gpu = common::gpu();
    for scene_name in ["open-quad", "open-box", "non-manifold", "touching"] {
        let scene = builtin_scene(scene_name).expect("scene");
        for method in [VolumeMethod::ZPass, VolumeMethod::ZFail] {
            for normalize in [Normalize::Seed, Normalize::Subpass] {
                let options = ShadowVolumeOptions { method, normalize, ..seed() };
                let iou = projected_outline_iou(&gpu, &scene, options);
                println!("{scene_name} {method:?} {}: IoU {iou:.4}", normalize.name());
                assert!(iou >= 0.99, "{scene_name} {method:?} {}: intersection over union {iou:.4}", normalize.name());
            }
        }
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn camera_inside_a_volume_needs_zfail_and_auto_chooses_it() {
    let gpu = common::gpu();
    let scene = builtin_scene("inside").expect("scene");
    let reference =
        render(&gpu, &scene, StencilMode::Reference, ShadowVolumeOptions { method: VolumeMethod::ZFail, ..seed() });
    let auto = render(&gpu, &scene, StencilMode::Emulated, seed());
    assert!(auto.stats.zfail, "auto must choose z-fail with the camera inside the slab's volume");
    assert_eq!(rgb_differences(&auto.output.image, &reference.output.image), 0);
    let zpass =
        render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions { method: VolumeMethod::ZPass, ..seed() });
    let wrong = rgb_differences(&zpass.output.image, &reference.output.image);
    assert!(
        wrong > (SIZE.0 * SIZE.1 / 10) as usize,
        "z-pass should visibly fail inside a volume ({wrong} pixels differ)"
    );

    // Same shadow as the analytic answer: the ground under the camera is in the slab's shadow,
    // ground far beyond the slab's shadow is lit.
    let unshadowed = lit(&gpu, &scene);
    let mask = shadow_mask(&auto.output.image, &unshadowed);
    let nostencil::Light::Directional { direction } = scene.light() else { panic!() };
    let slab = scene.object("slab").expect("slab");
    let under_slab = |p: Vec3| {
        // Project the ground point up the light onto the slab's bottom face (y = 2.85).
        let q = p - direction * ((2.85 - p.y) / -direction.y);
        let local = slab.transform.inverse().transform_point3(q);
        local.x.abs() < 0.5 && local.z.abs() < 0.5
    };
    let (mut agree, mut total) = (0, 0);
    for y in SIZE.1 / 2..SIZE.1 {
        for x in 0..SIZE.0 {
            if let Some(p) = common::ground_point(&scene.camera, (x, y), SIZE, 0.0) {
                total += 1;
                agree += (under_slab(p) == mask[(y * SIZE.0 + x) as usize]) as u32;
            }
        }
    }
    assert!(agree as f64 / total as f64 > 0.98, "{agree}/{total} ground pixels agree with the analytic shadow");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn background_behind_volumes_is_never_darkened() {
    let gpu = common::gpu();
    for name in ["default", "point-light", "overlap"] {
        let scene = builtin_scene(name).expect("scene");
        let unshadowed = lit(&gpu, &scene);
        let sky = common::srgb8(scene.background);
        for method in [VolumeMethod::ZPass, VolumeMethod::ZFail] {
            let frame = render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions { method, ..seed() });
            let image = &frame.output.image;
            let darkened_sky = image
                .chunks_exact(4)
                .zip(unshadowed.chunks_exact(4))
                .filter(|(p, q)| q[..3] == sky && p[..3] != sky)
                .count();
            assert_eq!(darkened_sky, 0, "{name} {method:?}: background pixels darkened");
            // Not vacuous: the frame shows its shadows and the sky.
            let shadowed = shadow_mask(image, &unshadowed).iter().filter(|s| **s).count();
            let sky_pixels = unshadowed.chunks_exact(4).filter(|q| q[..3] == sky).count();
            assert!(
                shadowed > 50 && sky_pixels > 50,
                "{name} {method:?}: {shadowed} shadowed, {sky_pixels} sky pixels"
            );
        }
    }
    common::assert_no_validation_messages(&gpu);
}

/// Each caster is classified once, with its reason, and its counter capacity reported: a
/// two-sided caster counts 2 per crossing of a closed part, so it holds half as many.
#[test]
fn casters_report_their_path_reason_and_capacity() {
    let gpu = common::gpu();
    let expected = [
        ("open-quad", "quad", "two-sided", "open (4 boundary edges)"),
        ("open-box", "open box", "two-sided", "open (4 boundary edges)"),
        // The spine's first two pages run it the same way: adjacency sees that as a winding flip.
        (
            "non-manifold",
            "fan",
            "two-sided",
            "open (9 boundary edges), non-manifold (1 edge with more than two faces), inconsistently wound (1 edge)",
        ),
        ("non-manifold", "flipped box", "two-sided", "inconsistently wound (3 edges)"),
        ("touching", "edge pair", "two-sided", "non-manifold (1 edge with more than two faces)"),
        ("touching", "corner pair", "silhouette", "closed and consistently wound"),
        ("box", "box", "silhouette", "closed and consistently wound"),
    ];
    for k in [1u8, 4] {
        for (scene_name, object, path, reason) in expected {
            let scene = builtin_scene(scene_name).expect("scene");
            let options = ShadowVolumeOptions { increment: k, ..seed() };
            let frame = try_render(
                &gpu,
                &scene,
                StencilMode::Emulated,
                ShadowMode::Modulate,
                options,
                (64, 48),
                ShadowTone::default(),
            )
            .expect("frame");
            let report = frame.stats.casters.iter().find(|c| c.object == object).expect("the caster is reported");
            assert_eq!((report.path, report.reason.as_str()), (path, reason), "{scene_name}/{object}");
            let per_crossing = if path == "two-sided" { 2 } else { 1 };
            assert_eq!(report.capacity, 255 / u32::from(k) / per_crossing, "{scene_name}/{object} k={k}");
            assert_eq!(frame.stats.casters.len(), scene.objects.iter().filter(|o| o.casts_shadow).count());
        }
    }
    common::assert_no_validation_messages(&gpu);
}

/// A caster no path can use (every triangle degenerate) casts nothing, and the renderer names
/// it in a warning with the reason; the frame still renders.
#[test]
fn a_caster_that_cannot_cast_is_named_in_a_warning() {
    let gpu = common::gpu();
    let mut scene = builtin_scene("box").expect("scene");
    let needle = scene.add_mesh(
        "needle",
        MeshData {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
            normals: vec![Vec3::Y; 3],
            uvs: vec![],
            indices: vec![0, 1, 2],
        },
    );
    scene.add_object("flat needle", needle, Mat4::from_translation(Vec3::Y), Vec3::ONE, true);
    let options = RenderOptions {
        width: 64,
        height: 48,
        technique: technique("shadow-volume"),
        shadow_volume: ShadowVolumeOptions::default(),
        ..Default::default()
    };
    let frame = render_scene(&gpu, &scene, &options).expect("the frame renders without the needle");
    assert_eq!(frame.warnings.len(), 1, "{:?}", frame.warnings);
    let warning = &frame.warnings[0];
    assert!(warning.contains("flat needle") && warning.contains("no triangle"), "{warning}");
    common::assert_no_validation_messages(&gpu);
}

/// `nostencil profile` prints each caster's path, reason and capacity, in the table and in JSON.
#[test]
fn profile_reports_each_casters_path_and_capacity() {
    let args =
        ["profile", "--technique", "shadow-volume", "--scene", "touching", "--size", "64x48", "--increment", "2"];
    let (table, _) = common::run_ok(&args);
    assert!(
        table.contains("caster 'edge pair': two-sided (non-manifold (1 edge with more than two faces)), capacity 63"),
        "{table}"
    );
    assert!(
        table.contains("caster 'corner pair': silhouette (closed and consistently wound), capacity 127"),
        "{table}"
    );
    let (json, _) = common::run_ok(&[&args[..], &["--format", "json"]].concat());
    let report: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    let casters = &report["technique_stats"]["casters"];
    assert_eq!(casters[0]["object"], "edge pair", "{json}");
    assert_eq!(casters[0]["path"], "two-sided", "{json}");
    assert_eq!(casters[0]["capacity"], 63, "{json}");
    assert_eq!(casters[1]["path"], "silhouette", "{json}");
}

/// Under a point light the shadow is no parallel projection: the ground pixels the volumes
/// darken must be those whose ray to the light hits a casting triangle, from either side
/// (`mesh::ray::in_shadow`, on the CPU), in z-pass and in z-fail, and emulated must equal the
/// reference.
#[test]
fn open_casters_under_a_point_light_shadow_what_the_cpu_ray_cast_finds() {
    use nostencil::mesh::ray::{in_shadow, PlacedMesh};
    const BIG: (u32, u32) = (192, 144);
    let gpu = common::gpu();
    for scene_name in ["open-quad", "open-box", "non-manifold", "touching"] {
        let mut scene = builtin_scene(scene_name).expect("scene");
        scene.set_light(nostencil::Light::Point { position: Vec3::new(-1.5, 6.0, 1.0) });
        let casters: Vec<PlacedMesh> = scene
            .objects
            .iter()
            .filter(|o| o.casts_shadow)
            .map(|o| PlacedMesh {
                positions: &scene.meshes[o.mesh].data.positions,
                indices: &scene.meshes[o.mesh].data.indices,
                model: o.transform,
            })
            .collect();
        let nostencil::Light::Point { position } = scene.light() else { unreachable!() };
        let light = nostencil::mesh::Light::Point(position);
        let unshadowed = lit_sized(&gpu, &scene, BIG);
        let mut without = scene.clone();
        without.objects.retain(|o| !o.casts_shadow);
        let background = lit_sized(&gpu, &without, BIG);
        for method in [VolumeMethod::ZPass, VolumeMethod::ZFail] {
            let options = ShadowVolumeOptions { method, ..seed() };
            let emulated = render_sized(&gpu, &scene, StencilMode::Emulated, options, BIG);
            let reference = render_sized(&gpu, &scene, StencilMode::Reference, options, BIG);
            let differing = rgb_differences(&emulated.output.image, &reference.output.image);
            assert_eq!(differing, 0, "{scene_name} {method:?}: emulated and reference differ");
            let mask = shadow_mask(&emulated.output.image, &unshadowed);
            let (mut both, mut either) = (0, 0);
            for y in 0..BIG.1 {
                for x in 0..BIG.0 {
                    let i = (y * BIG.0 + x) as usize;
                    if unshadowed.get_pixel(x, y) != background.get_pixel(x, y) {
                        continue; // a caster, not ground
                    }
                    let expected = common::ground_point(&scene.camera, (x, y), BIG, 0.0)
                        .is_some_and(|p| p.x.abs() < 7.0 && p.z.abs() < 7.0 && in_shadow(light, &casters, p));
                    both += (expected && mask[i]) as u32;
                    either += (expected || mask[i]) as u32;
                }
            }
            let iou = both as f64 / either as f64;
            println!("{scene_name} point light {method:?}: IoU {iou:.4} over {either} pixels");
            assert!(either > 200, "{scene_name} {method:?}: the shadow is too small to judge ({either} pixels)");
            assert!(iou >= 0.99, "{scene_name} {method:?}: intersection over union {iou:.4}");
        }
    }
    common::assert_no_validation_messages(&gpu);
}

/// The command line prints a technique's warnings on stderr: a glTF file whose second mesh is
/// one degenerate triangle renders, the sheet casts, and the needle is named with its reason.
#[test]
fn the_command_line_names_a_mesh_that_casts_no_shadow() {
    use base64::Engine;
    let positions: [[f32; 3]; 7] = [
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
        [0.0, 2.0, 0.0],
        [1.0, 2.0, 0.0],
        [2.0, 2.0, 0.0],
    ];
    let indices: [u16; 10] = [0, 2, 1, 0, 3, 2, 0, 1, 2, 0]; // the last one pads to 4 bytes
    let mut bytes: Vec<u8> = positions.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
    bytes.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let uri =
        format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bytes));
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"mesh": 1}],
        "meshes": [
            {"name": "sheet", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]},
            {"name": "needle", "primitives": [{"attributes": {"POSITION": 2}, "indices": 3}]}
        ],
        "buffers": [{"byteLength": bytes.len(), "uri": uri}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 36},
            {"buffer": 0, "byteOffset": 84, "byteLength": 12},
            {"buffer": 0, "byteOffset": 96, "byteLength": 6}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 1, 0], "max": [1, 1, 1]},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 2, 0], "max": [2, 2, 0]},
            {"bufferView": 3, "componentType": 5123, "count": 3, "type": "SCALAR"}
        ]
    });
    let dir = common::scratch_dir("needle-warning");
    let (file, out) = (dir.join("needle.gltf"), dir.join("needle.png"));
    std::fs::write(&file, gltf.to_string()).expect("write the glTF");
    let (_, stderr) = common::run_ok(&[
        "render",
        "--technique",
        "shadow-volume",
        "--scene",
        file.to_str().expect("path"),
        "--size",
        "64x48",
        "--out",
        out.to_str().expect("path"),
    ]);
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.starts_with("nostencil: warning:")).collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    assert!(
        warnings[0].contains("shadow-volume")
            && warnings[0].contains("needle")
            && warnings[0].contains("no triangle with an area"),
        "{stderr}"
    );
    assert!(!stderr.contains("'sheet"), "the sheet casts: {stderr}");
}

/// A caster mirrored by its transform (negative determinant: every winding flips on screen, its
/// triangles turned to face out in the world as the glTF loader turns them) and one wound
/// inside out (closed, normals pointing in) still shadow their projected outline.
#[test]
fn mirrored_and_inside_out_casters_shadow_their_projected_outline() {
    let gpu = common::gpu();
    // Mirrored as the glTF loader places a mirrored node: the transform mirrors, and the mesh's
    // triangles are turned so that they face out in the world.
    let mut mirrored = builtin_scene("box").expect("scene");
    for object in mirrored.objects.iter_mut().filter(|o| o.name == "box") {
        object.transform *= Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    }
    let mesh = mirrored.object("box").expect("box").mesh;
    mirrored.meshes[mesh].data.indices.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
    let mut inside_out = builtin_scene("box").expect("scene");
    let mesh = inside_out.object("box").expect("box").mesh;
    for t in inside_out.meshes[mesh].data.indices.chunks_exact_mut(3) {
        t.swap(1, 2);
    }
    for (label, scene) in [("mirrored", &mirrored), ("inside out", &inside_out)] {
        for method in [VolumeMethod::ZPass, VolumeMethod::ZFail] {
            let options = ShadowVolumeOptions { method, ..seed() };
            let reference = render_sized(&gpu, scene, StencilMode::Reference, options, (128, 96));
            let emulated = render_sized(&gpu, scene, StencilMode::Emulated, options, (128, 96));
            assert_eq!(rgb_differences(&emulated.output.image, &reference.output.image), 0, "{label} {method:?}");
            let iou = projected_outline_iou(&gpu, scene, options);
            assert!(iou >= 0.99, "{label} {method:?}: intersection over union {iou:.4}");
        }
    }
    // The mirrored box is a solid wound as its own space should be: it keeps the silhouette path.
    let frame = render_sized(&gpu, &mirrored, StencilMode::Emulated, seed(), (128, 96));
    let paths: Vec<&str> = frame.stats.casters.iter().map(|c| c.path).collect();
    assert_eq!(paths, ["silhouette"], "{:?}", frame.stats.casters);
    common::assert_no_validation_messages(&gpu);
}
