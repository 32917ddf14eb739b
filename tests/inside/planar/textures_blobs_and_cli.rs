//! The seed's render-texture quad and the other two shadows (the shadow texture, the blobs),
//! the command line's errors and profile, and a renderer following a walk.

use super::*;

#[test]
fn the_seeds_render_texture_quad_holds_the_shadow_where_the_projection_puts_it() {
    // `shadow-texture --render-texture-on quad`: the casters' texture laid on one quad on the
    // plane (the seed's way). The quad lies around the CPU projection of every caster, every
    // pixel it darkens lies inside it, its shadow covers the CPU projection's as closely as the
    // texture's texels allow (better with a bigger texture: the size is honoured), and on a
    // ground larger than the quad it shows what the receivers' lookup shows.
    let gpu = common::gpu();
    let tilted = GivenPlane { normal: [0.0, 3.0, 1.0], height: 0.0 };
    for (name, time, given) in [("character", 0.3, None), ("character-point", 0.3, None), ("slope", 0.5, Some(tilted))]
    {
        let scene = builtin_scene_at(name, time).expect("scene");
        let plane = planar::receiver_plane(&scene, given.as_ref()).expect("plane");
        let base = PlanarOptions { plane: given, ..Default::default() };
        let unshadowed = render_with(
            &gpu,
            &scene,
            technique("planar"),
            SIZE,
            StencilMode::Emulated,
            PlanarOptions { shadows: false, ..base },
        )
        .expect("scene");
        let receivers = receiver_mask(&unshadowed.output.image);
        let texture = |texture_on, texture_size| {
            let options = PlanarOptions { texture_on, texture_size, ..base };
            let frame = render_with(&gpu, &scene, technique("shadow-texture"), SIZE, StencilMode::Emulated, options)
                .expect("shadow texture");
            changed(&frame.output.image, &unshadowed.output.image)
        };
        let on_quad = texture(TextureShadowOn::Quad, 128);
        let on_receivers = texture(TextureShadowOn::Receivers, 128);
        let casters = |i: usize| !plane.receivers[i];
        let cpu = cpu_shadow_mask(
            &scene,
            &triangles_projected_by(&scene, casters, |p| plane.plane.project(p, &scene.light())),
        );
        let corners = planar::texture_quad::shadow_quad(&scene, &plane).expect("casters");
        let quad_pixels =
            cpu_shadow_mask(&scene, &[[corners[0], corners[1], corners[2]], [corners[0], corners[2], corners[3]]]);
        let outside = on_quad.iter().zip(&quad_pixels).filter(|(d, q)| **d && !**q).count();
        let everywhere = vec![true; receivers.len()];
        let with_cpu = iou(&on_quad, &cpu, &receivers);
        let with_receivers = iou(&on_quad, &on_receivers, &everywhere);
        let coarse = iou(&texture(TextureShadowOn::Quad, 16), &cpu, &receivers);
        let fine = iou(&texture(TextureShadowOn::Quad, 512), &cpu, &receivers);
        eprintln!(
            "{name}: quad shadow IoU {with_cpu:.3} with the CPU projection (16 texels {coarse:.3}, 512 texels {fine:.3}), {with_receivers:.3} with the receivers' lookup; {outside} darkened pixels outside the quad"
        );
        assert!(on_quad.iter().filter(|d| **d).count() > 100, "{name}: no quad shadow");
        assert_eq!(outside, 0, "{name}: {outside} pixels darkened outside the quad");
        assert!(with_cpu > 0.8, "{name}: quad shadow vs CPU projection IoU {with_cpu}");
        assert!(with_receivers > 0.95, "{name}: quad vs receivers IoU {with_receivers}");
        assert!(fine > coarse, "{name}: a 512-texel texture ({fine}) fits no better than 16 texels ({coarse})");
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn bad_input_gets_a_clear_error() {
    let gpu = common::gpu();
    // No ground to project onto.
    let mut scene = builtin_scene_at("character", 0.0).expect("scene");
    scene.objects.retain(|o| o.name != "ground");
    let error =
        render_with(&gpu, &scene, technique("planar"), (64, 64), StencilMode::Emulated, PlanarOptions::default())
            .err()
            .expect("refused")
            .to_string();
    assert!(error.contains("no flat horizontal receiver"), "{error}");

    // More joints than the 16 KiB palette holds.
    let mut scene = builtin_scene_at("character", 0.0).expect("scene");
    if let Some(skin) = scene.objects.iter_mut().find_map(|o| o.skin.as_mut()) {
        skin.joint_matrices = vec![Mat4::IDENTITY; nostencil::scene::MAX_JOINTS + 1];
    }
    let error =
        render_with(&gpu, &scene, technique("planar"), (64, 64), StencilMode::Emulated, PlanarOptions::default())
            .err()
            .expect("refused")
            .to_string();
    assert!(error.contains("at most 256"), "{error}");

    // Malformed files, through the command line with the planar technique: one line naming the
    // file and the problem.
    let good = common::test_asset("RiggedSimple.glb");
    let dir = common::scratch_dir("planar-bad-input");
    let bytes = std::fs::read(&good).expect("read");
    let truncated = dir.join("truncated.glb");
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).expect("write");
    let not_gltf = dir.join("garbage.gltf");
    std::fs::write(&not_gltf, b"{ this is not json").expect("write");
    for bad in [&truncated, &not_gltf] {
        let out = dir.join("out.png");
        let (bad_path, out_path) = (bad.to_str().expect("utf-8 path"), out.to_str().expect("utf-8 path"));
        let err = common::run_err(&[
            "render",
            "--technique",
            "planar",
            "--size",
            "64x64",
            "--scene",
            bad_path,
            "--out",
            out_path,
        ]);
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        let name = bad.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        assert!(err.contains(&name), "the error names the file: {err}");
        assert!(!out.exists());
    }
    common::assert_no_validation_messages(&gpu);
}

/// The other two shadows of seed 001, checked against the projected-mesh shadow.
#[test]
fn shadow_texture_covers_the_planar_shadow_and_blobs_sit_under_the_casters() {
    let gpu = common::gpu();
    for name in ["character", "character-point"] {
        let scene = builtin_scene_at(name, 0.3).expect("scene");
        let unshadowed = render(&gpu, &scene, StencilMode::Emulated, false);
        let receivers = receiver_mask(&unshadowed.output.image);
        let planar_mask =
            changed(&render(&gpu, &scene, StencilMode::Emulated, true).output.image, &unshadowed.output.image);

        let options = PlanarOptions::default();
        let texture = render_with(&gpu, &scene, technique("shadow-texture"), SIZE, StencilMode::Emulated, options)
            .expect("shadow texture");
        let texture_mask = changed(&texture.output.image, &unshadowed.output.image);
        let (mut both, mut either, mut exact, mut darkened) = (0, 0, 0, 0);
        for (i, (p, q)) in texture.output.image.chunks_exact(4).zip(unshadowed.output.image.chunks_exact(4)).enumerate()
        {
            both += (texture_mask[i] && planar_mask[i]) as usize;
            either += (texture_mask[i] || planar_mask[i]) as usize;
            if texture_mask[i] {
                assert!(receivers[i], "{name}: pixel {i} darkened off the receivers");
                darkened += 1;
                let once = [darken(q[0], FACTOR), darken(q[1], FACTOR), darken(q[2], FACTOR)];
                assert!(
                    (0..3).all(|c| p[c] + 1 >= once[c]),
                    "{name}: pixel {i} darker than one shadow: {p:?} vs {once:?}"
                );
                exact += darkened_once(p, q, FACTOR) as usize;
            }
        }
        // Same silhouette up to the texture's texels and filtering at the edges.
        assert!(both * 100 >= either * 80, "{name}: shadow texture and planar overlap {both} of {either} pixels");
        assert!(
            exact * 100 >= darkened * 70,
            "{name}: only {exact} of {darkened} texture-shadow pixels at full factor"
        );

        let blob = render_with(&gpu, &scene, technique("blob"), SIZE, StencilMode::Emulated, options).expect("blob");
        let blob_mask = changed(&blob.output.image, &unshadowed.output.image);
        assert!(blob_mask.iter().zip(&receivers).all(|(b, r)| !b || *r), "{name}: blob off the receivers");
        // One blob under each foot: the lowest points of the two legs (boxes 4 and 5).
        let plane = planar::receiver_plane(&scene, None).expect("plane");
        let blobs = planar::blob::blobs(&scene, &plane, 1.0 - FACTOR as f32 / 255.0);
        assert_eq!(blobs.len(), 2, "{name}: {blobs:?}");
        let character = scene.object("character").expect("character");
        let data = &scene.meshes[character.mesh].data;
        for (leg, blob) in [96..120usize, 120..144].into_iter().zip(&blobs) {
            let foot = leg
                .map(|v| character.transform.transform_point3(data.positions[v]))
                .min_by(|a, b| a.y.total_cmp(&b.y))
                .expect("vertices");
            let offset = (foot - blob.centre) * Vec3::new(1.0, 0.0, 1.0);
            assert!(offset.length() < 0.12, "{name}: blob {blob:?} is not under the foot at {foot}");
        }
        let pixel_of = |p: Vec3| {
            let c = scene.camera.view_projection(SIZE.0 as f32 / SIZE.1 as f32) * p.extend(1.0);
            let (x, y) = ((c.x / c.w * 0.5 + 0.5) * SIZE.0 as f32, (c.y / c.w * 0.5 + 0.5) * SIZE.1 as f32);
            (y as u32 * SIZE.0 + x as u32) as usize
        };
        let darkened_under = blobs.iter().filter(|b| blob_mask[pixel_of(b.centre)]).count();
        assert!(darkened_under >= 1, "{name}: no blob visible under a foot");
        let under = blobs[0].centre;
        assert!(!blob_mask[pixel_of(under + Vec3::new(2.0, 0.0, 0.0))], "{name}: the blob reaches 2 m away");
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn profile_shows_each_shadow_kind() {
    for (technique, expected) in [
        ("blob", &["scene", "blob shadow"][..]),
        ("shadow-texture", &["shadow texture", "scene", "shadow texture receive"][..]),
        ("planar", &["scene (ambient)", "sun: planar shadow", "sun: shading", "transparent"][..]),
    ] {
        let (stdout, err) = common::run_ok(&[
            "profile",
            "--technique",
            technique,
            "--size",
            "96x64",
            "--format",
            "json",
            "--validation",
        ]);
        assert!(!err.contains("validation"), "{technique}: {err}");
        let json: serde_json::Value = serde_json::from_str(&stdout).expect("json");
        let names: Vec<&str> =
            json["passes"].as_array().expect("passes").iter().filter_map(|p| p["name"].as_str()).collect();
        assert_eq!(names, expected, "{technique}");
    }
}

#[test]
fn a_renderer_built_once_follows_the_walk_as_if_rebuilt_at_each_time() {
    // What the viewer does every frame: the scene built at 0 s, re-posed (`Scene::pose_at`:
    // joint palettes) and drawn by the same renderer, equals a scene built at that time, for
    // every technique that draws skinned meshes (GPU-skinned, or re-skinned on the CPU when the
    // palette changes), for the built-in walk and a glTF file's animation.
    let gpu = common::gpu();
    let rigged = common::test_asset("RiggedSimple.glb");
    type SceneAt<'a> = Box<dyn Fn(f32) -> Scene + 'a>;
    let sources: [(&str, SceneAt); 2] = [
        ("character", Box::new(|t| builtin_scene_at("character", t).expect("scene"))),
        ("RiggedSimple", Box::new(|t| scene_from_gltf(&rigged, t).expect("scene"))),
    ];
    let mut variants: Vec<(String, RenderOptions)> = [
        technique("lit"),
        technique("shadow-volume"),
        technique("silhouette"),
        technique("toon"),
        technique("outline"),
        technique("planar"),
        technique("blob"),
        technique("shadow-texture"),
        technique("shadow-map"),
        technique("shadow-texture-atlas"),
    ]
    .into_iter()
    .map(|technique| {
        (technique.name().to_owned(), RenderOptions { width: SIZE.0, height: SIZE.1, technique, ..Default::default() })
    })
    .collect();
    let mut hull = variants[2].1.clone();
    hull.cartoon.silhouette = nostencil::SilhouetteMethod::Hull;
    variants.push(("silhouette hull".into(), hull));
    for (name, build) in &sources {
        let start = build(0.0);
        for (variant, options) in &variants {
            let mut renderer = options.technique.build(&gpu, &start, options).expect("renderer");
            let first = render_scene(&gpu, &start, options).expect("frame").output.image;
            let mut moving = start.clone();
            let mut changed = 0;
            for time in [0.3, 0.6] {
                moving.pose_at(time).expect("pose");
                let live = renderer.frame_with(&moving).expect("frame").output.image;
                let mut rebuilt = build(time);
                // A glTF scene fits its ground (size and place) and camera to the pose it is
                // built in; keep the first ones.
                for (o, first) in rebuilt.objects.iter_mut().zip(&start.objects).filter(|(o, _)| o.rig.is_none()) {
                    o.transform = first.transform;
                    rebuilt.meshes[o.mesh] = start.meshes[first.mesh].clone();
                }
                rebuilt.camera = start.camera;
                let reference = render_scene(&gpu, &rebuilt, options).expect("frame").output.image;
                let differing = rgb_differences(&live, &reference);
                if options.technique.name() == "shadow-texture-atlas" {
                    // A skinned mesh's generated atlas is laid out from the pose it was built in,
                    // so its own texels sample the shadow map at other places: only the
                    // character's shading may differ (the ground's bake and the shadow agree).
                    assert!(differing < (SIZE.0 * SIZE.1 / 100) as usize, "{name} {variant} at {time}s: {differing}");
                } else {
                    assert_eq!(differing, 0, "{name} {variant} at {time}s");
                }
                changed += rgb_differences(&live, &first);
            }
            assert!(changed > 50, "{name} {variant}: the walk does not show ({changed} pixels moved)");
        }
    }
    common::assert_no_validation_messages(&gpu);
}
