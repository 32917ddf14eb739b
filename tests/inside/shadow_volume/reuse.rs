//! Volumes across frames: unmoved volumes and cullings reused, moved ones built again, and the
//! shadow mesh's volumes (extruded by the shader) against the CPU's indices, still and moving.

use super::*;

/// The next frame of `renderer` for `scene`: its image and what the volumes report of the first
/// light.
fn next_frame(
    renderer: &mut nostencil::SceneRenderer<'_>,
    scene: &Scene,
) -> (RgbaImage, nostencil::stats::LightReport) {
    let frame = renderer.frame_with(scene).expect("frame");
    let stats = frame.stats::<nostencil::stats::ShadowVolumeStats>().expect("statistics").clone();
    (frame.output.image, stats.lights[0].clone())
}

/// A volume whose light, reach and caster did not move is drawn from the buffers of the frames
/// before, not built again, and draws the same image; where the light moved, or one caster
/// turned, exactly those volumes are built again, and the frame equals a fresh renderer's.
#[test]
fn unmoved_volumes_are_reused_and_moved_ones_built_again_to_the_same_image() {
    let gpu = common::gpu();
    // Several casters, none skinned (a skinned caster is built again every frame whatever moved).
    let base = builtin_scene("overlap").expect("scene");
    assert!(
        base.objects.iter().all(|o| o.skin.is_none()) && base.objects.iter().filter(|o| o.casts_shadow).count() > 1
    );
    for stencil in [StencilMode::Emulated, StencilMode::Reference] {
        let options = RenderOptions {
            width: SIZE.0,
            height: SIZE.1,
            samples: 1,
            stencil,
            technique: technique("shadow-volume"),
            ..Default::default()
        };
        let mut renderer = options.technique.build(&gpu, &base, &options).expect("renderer");
        let (first, built) = next_frame(&mut renderer, &base);
        assert!(built.volumes > 0 && built.reused == 0, "{stencil:?}: {built:?}");
        let (second, again) = next_frame(&mut renderer, &base);
        assert_eq!(again.reused, again.volumes, "{stencil:?}: nothing moved, every volume reused: {again:?}");
        assert!(first == second, "{stencil:?}: the reused volumes drew another image");

        let mut moved_light = base.clone();
        let Light::Directional { direction } = moved_light.lights[0].geometry() else { panic!("a sun") };
        moved_light.lights[0]
            .set_geometry(Light::Directional { direction: (direction + Vec3::new(0.2, 0.0, 0.1)).normalize() });
        let mut turned = base.clone();
        let caster = turned.objects.iter().position(|o| o.casts_shadow).expect("a caster");
        turned.objects[caster].transform = Mat4::from_rotation_y(0.4) * turned.objects[caster].transform;
        for (what, moved, most_reused) in
            [("a moved light", &moved_light, 0), ("a turned caster", &turned, again.volumes - 1)]
        {
            let (image, report) = next_frame(&mut renderer, moved);
            assert!(report.reused <= most_reused, "{stencil:?}, {what}: {report:?}");
            let mut fresh = options.technique.build(&gpu, &base, &options).expect("renderer");
            let (expected, _) = next_frame(&mut fresh, moved);
            assert!(image == expected, "{stencil:?}, {what}: the rebuilt volumes drew another image");
            // Back to where it was: built again for the base scene, the base image.
            let (back, _) = next_frame(&mut renderer, &base);
            assert!(back == first, "{stencil:?}, {what}: not the base image after moving back");
        }
    }
    common::assert_no_validation_messages(&gpu);
}

/// The culling a light decided (`--cull-casters`) is kept while neither the light nor any caster
/// moves: the next frame culls the same casters without deciding again, and draws the same
/// image; a moved light or a turned caster decides again, to a fresh renderer's image; and a
/// scene with a skinned caster, which moves without a transform, decides every frame.
#[test]
fn an_unmoved_culling_is_kept_and_a_moved_one_decided_again() {
    let gpu = common::gpu();
    let base = nested_scene();
    let options = RenderOptions {
        width: SIZE.0,
        height: SIZE.1,
        samples: 1,
        technique: technique("shadow-volume"),
        shadow_volume: ShadowVolumeOptions { cull_casters: true, ..Default::default() },
        ..Default::default()
    };
    let mut renderer = options.technique.build(&gpu, &base, &options).expect("renderer");
    let (first, decided) = next_frame(&mut renderer, &base);
    assert!(decided.culled == 2 && !decided.culling_reused, "{decided:?}");
    let (second, kept) = next_frame(&mut renderer, &base);
    assert!(kept.culling_reused && kept.culled == 2, "nothing moved, the culling is kept: {kept:?}");
    assert!(first == second, "the kept culling drew another image");

    let mut moved_light = base.clone();
    let Light::Directional { direction } = moved_light.lights[0].geometry() else { panic!("a sun") };
    moved_light.lights[0]
        .set_geometry(Light::Directional { direction: (direction + Vec3::new(0.05, 0.0, 0.0)).normalize() });
    let mut turned = base.clone();
    let roof = turned.objects.iter().position(|o| o.name == "roof").expect("the roof");
    turned.objects[roof].transform = Mat4::from_translation(Vec3::new(3.0, 0.0, 0.0)) * turned.objects[roof].transform;
    for (what, moved) in [("a moved light", &moved_light), ("a moved roof", &turned)] {
        let (image, report) = next_frame(&mut renderer, moved);
        assert!(!report.culling_reused, "{what}: decided again: {report:?}");
        let mut fresh = options.technique.build(&gpu, moved, &options).expect("renderer");
        let (expected, fresh_report) = next_frame(&mut fresh, moved);
        assert_eq!(report.culled, fresh_report.culled, "{what}");
        assert!(image == expected, "{what}: another image than a fresh renderer's");
        let (back, report) = next_frame(&mut renderer, &base);
        assert!(!report.culling_reused && back == first, "{what}: moved back, decided again, the base image");
    }
    // The roof moved away: the boxes are in its shadow no more.
    let (_, away) = next_frame(&mut options.technique.build(&gpu, &turned, &options).expect("renderer"), &turned);
    assert_eq!(away.culled, 0, "{away:?}");

    let walking = builtin_scene("default").expect("scene");
    assert!(walking.objects.iter().any(|o| o.casts_shadow && o.skin.is_some()), "a skinned caster");
    let mut renderer = options.technique.build(&gpu, &walking, &options).expect("renderer");
    for _ in 0..2 {
        let (_, report) = next_frame(&mut renderer, &walking);
        assert!(!report.culling_reused, "a skinned caster: decided every frame: {report:?}");
    }
    common::assert_no_validation_messages(&gpu);
}

/// Volumes extruded by the shadow mesh (`--volume-extrusion shader`: the vertex shader decides
/// facing, walls, caps and their multiplicities) draw the bytes of the volumes whose indices
/// the CPU chose, over closed, open, non-manifold and touching casters, a skinned one and a
/// mirrored one (both keep the CPU's indices), under a sun, a point light and several lights,
/// in both counting methods, on both counters (every pair of them on the scenes of several
/// lights and of a mirrored caster, z-pass emulated and z-fail reference on the rest, the pairs
/// tests/inside/plan.rs draws at 4x), clipped or reaching infinity.
#[test]
fn volumes_extruded_by_the_shader_draw_the_bytes_of_cpu_chosen_indices() {
    use nostencil::technique::shadow_volume::VolumeExtrusion;
    let gpu = common::gpu();
    let mut mirrored = builtin_scene("overlap").expect("scene");
    let turned = mirrored.objects.iter().position(|o| o.casts_shadow).expect("a caster");
    mirrored.objects[turned].transform *= Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    let mut scenes: Vec<(&str, Scene)> = ["default", "point-light", "non-manifold", "open-box", "touching", "lights"]
        .into_iter()
        .map(|name| (name, builtin_scene(name).expect("scene")))
        .collect();
    scenes.push(("overlap, one caster mirrored", mirrored));
    let mut extruded_somewhere = 0;
    for (name, scene) in &scenes {
        let rigid = scene.objects.iter().filter(|o| o.casts_shadow && o.skin.is_none()).count();
        // Every counter and counting method on the scenes of several lights and of a mirrored
        // caster; elsewhere the two pairs that tests/inside/plan.rs also draws at 4x.
        let every_pair = *name == "lights" || name.contains("mirrored");
        for (stencil, method) in [
            (StencilMode::Emulated, VolumeMethod::ZPass),
            (StencilMode::Reference, VolumeMethod::ZFail),
            (StencilMode::Emulated, VolumeMethod::ZFail),
            (StencilMode::Reference, VolumeMethod::ZPass),
        ]
        .into_iter()
        .take(if every_pair { 4 } else { 2 })
        {
            for clip_volumes in [true, false] {
                let options = ShadowVolumeOptions { method, clip_volumes, ..Default::default() };
                let shader = ShadowVolumeOptions { extrusion: VolumeExtrusion::Shader, ..options };
                let label = format!("{name}, {stencil:?}, {method:?}, clipped {clip_volumes}");
                let indexed = render_additive(&gpu, scene, stencil, options);
                let extruded = render_additive(&gpu, scene, stencil, shader);
                assert!(extruded.output.image == indexed.output.image, "{label}: the images differ");
                let count: usize = extruded.stats.lights.iter().map(|l| l.extruded).sum();
                let drawn: usize = extruded.stats.lights.iter().map(|l| l.volumes).sum();
                assert!(indexed.stats.lights.iter().all(|l| l.extruded == 0), "{label}: indices extrude nothing");
                // Every drawn volume of a rigid, unmirrored caster is the shader's.
                let mirrored_casters = usize::from(name.contains("mirrored"));
                assert!(count <= drawn && count <= rigid * scene.lights.len(), "{label}: {count} of {drawn}");
                if rigid > mirrored_casters && drawn > 0 {
                    assert!(count > 0, "{label}: no volume extruded by the shader");
                }
                extruded_somewhere += count;
            }
        }
    }
    assert!(extruded_somewhere > 50, "only {extruded_somewhere} volumes extruded by the shader");
    common::assert_no_validation_messages(&gpu);
}

/// Frame after frame, as the sun turns and a caster turns with it, the shadow mesh's volumes
/// (nothing rebuilt on the CPU) draw what the CPU's indices (rebuilt as things move) draw.
#[test]
fn the_shadow_mesh_follows_a_moving_light_and_caster_frame_after_frame() {
    use nostencil::technique::shadow_volume::VolumeExtrusion;
    let gpu = common::gpu();
    let base = builtin_scene("overlap").expect("scene");
    let build = |extrusion| {
        let options = RenderOptions {
            width: SIZE.0,
            height: SIZE.1,
            samples: 1,
            technique: technique("shadow-volume"),
            shadow_volume: ShadowVolumeOptions { extrusion, ..Default::default() },
            ..Default::default()
        };
        options.technique.build(&gpu, &base, &options).expect("renderer")
    };
    let (mut indexed, mut extruded) = (build(VolumeExtrusion::Indices), build(VolumeExtrusion::Shader));
    let caster = base.objects.iter().position(|o| o.casts_shadow).expect("a caster");
    let mut scene = base.clone();
    for step in 0..6 {
        let angle = step as f32 * 0.3;
        let Light::Directional { direction } = base.lights[0].geometry() else { panic!("a sun") };
        let turned = Mat4::from_rotation_y(angle).transform_vector3(direction);
        scene.lights[0].set_geometry(Light::Directional { direction: turned.normalize() });
        scene.objects[caster].transform = Mat4::from_rotation_y(angle * 0.5) * base.objects[caster].transform;
        let (expected, built) = next_frame(&mut indexed, &scene);
        let (image, report) = next_frame(&mut extruded, &scene);
        assert!(image == expected, "frame {step}: the images differ");
        assert!(step == 0 || built.reused < built.volumes, "frame {step}: the indices were rebuilt: {built:?}");
        assert_eq!(report.extruded, report.volumes, "frame {step}: {report:?}");
    }
    common::assert_no_validation_messages(&gpu);
}
