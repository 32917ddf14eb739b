//! Emulated equals the real stencil pixel for pixel over the scenes and options: every built-in
//! scene in every normalisation (clipped or not), the k/D sweep, the additive loop, a narrow
//! spot's cone, culled casters, split near caps and a tinted shadow.

use super::*;

/// The shadow factors of the k/D sweep: the default 102, and 64 and 128, where the
/// normalisation needs a different number of iterations (docs/design/blend-rounding.md).
const SWEEP_DARKNESS: [u8; 3] = [64, 102, 128];

/// k and D change only the blend arithmetic of the count and its normalisation, not which
/// pixels a volume covers: on the `overlap` scene (stacked casters, the deepest counts of the
/// built-in scenes), z-fail and the scene's own choice, every k in {1, 2, 4, 8} and D in
/// {64, 102, 128} in every normalisation equals the reference pixel for pixel (the subpass
/// apply counts no saturation). Every scene's geometry is proven at k = 1, D = 102 by
/// `emulated_equals_reference_on_every_scene_clipped_or_not`; every count's seed and max
/// normalisation at seven (k, D), read back from the GPU, by
/// `normalisation_table_is_read_back_from_the_gpu` (the subpass apply reads the count itself); the
/// count itself (alpha = k x the stencil's, k = 1 and 4, per sample) by
/// tests/inside/msaa_samples.rs. (This sweep once ran on every built-in scene: about 940 frames,
/// 50 s.)
#[test]
fn increment_and_darkness_change_only_the_blend_arithmetic() {
    let gpu = common::gpu();
    let scene = builtin_scene("overlap").expect("scene");
    let unshadowed = lit(&gpu, &scene);
    for (method, d) in
        [VolumeMethod::Auto, VolumeMethod::ZFail].into_iter().flat_map(|m| SWEEP_DARKNESS.map(|d| (m, d)))
    {
        let base = ShadowVolumeOptions { method, ..seed() };
        let tone = ShadowTone::Grey(d);
        let reference = render_toned(&gpu, &scene, StencilMode::Reference, base, tone);
        let shadowed_pixels = shadow_mask(&reference.output.image, &unshadowed).iter().filter(|s| **s).count();
        assert!(shadowed_pixels > 50, "the reference shows no shadow ({shadowed_pixels} pixels)");
        for k in [1u8, 2, 4, 8] {
            for &normalize in Normalize::ALL {
                let options = ShadowVolumeOptions { increment: k, normalize, ..base };
                let emulated = render_toned(&gpu, &scene, StencilMode::Emulated, options, tone);
                let what = format!("{method:?} k={k} D={d} {}", normalize.name());
                // Only the subpass apply counts saturation without the probe.
                let measured = (normalize == Normalize::Subpass).then_some(0);
                assert_eq!(emulated.stats.saturated_samples, measured, "{what}");
                let differing = rgb_differences(&emulated.output.image, &reference.output.image);
                assert_eq!(differing, 0, "{what}: {differing} pixels differ");
            }
        }
    }
    common::assert_no_validation_messages(&gpu);
}

/// The normalisations the additive loop draws: `max` runs exactly `seed`'s passes there.
const ADDITIVE_NORMALISATIONS: [Normalize; 2] = [Normalize::Seed, Normalize::Subpass];

/// The additive loop (docs/shadow-volumes.md, "Several lights"), emulated against Ogre's
/// per-light stencil loop, at 1x: every built-in scene (the `lights` scene's three lights
/// among them), z-fail and the scene's own choice, the seed and subpass normalisations at k = 1, pixel for
/// pixel, and the subpass mask also on a device without fragment atomics. k = 4 (blend
/// arithmetic only, as `increment_and_darkness_change_only_the_blend_arithmetic` says) runs on
/// `overlap` and `lights`, the scenes with the deepest counts and the most lights.
/// tests/inside/plan.rs runs every scene's additive loop at 4x, and tests/inside/msaa_samples.rs
/// k = 4 at 4x. The max path is not drawn: in the additive loop its plan is the seed path's, pass
/// for pass (checked here on the plans, both counting methods, 1x and 4x), so it draws the same
/// frame.
#[test]
fn additive_emulated_equals_reference_on_every_scene() {
    for method in [VolumeMethod::ZPass, VolumeMethod::ZFail] {
        for samples in [1, 4] {
            let trace = |normalize| {
                let options = ShadowVolumeOptions { method, normalize, ..Default::default() };
                let lights = nostencil::technique::light_loop::PlannedLight::default_lights();
                let plan = shadow_volume::recipes::plan(
                    &options,
                    ShadowMode::Additive,
                    ShadowTone::default(),
                    StencilMode::Emulated,
                    samples,
                    &lights,
                );
                plan.expect("plan").expected_trace(|_| true)
            };
            assert_eq!(trace(Normalize::Max), trace(Normalize::Seed), "{method:?} {samples}x");
        }
    }
    let gpu = common::gpu();
    for (name, _) in BUILTIN_SCENES {
        let scene = builtin_scene(name).expect("scene");
        let unshadowed = lit(&gpu, &scene);
        let increments: &[u8] = if ["overlap", "lights"].contains(name) { &[1, 4] } else { &[1] };
        for method in [VolumeMethod::Auto, VolumeMethod::ZFail] {
            let base = ShadowVolumeOptions { method, ..Default::default() };
            assert_eq!(RenderOptions::default().shadow_mode, ShadowMode::Additive, "additive is the default");
            let reference = render_additive(&gpu, &scene, StencilMode::Reference, base);
            let darkened = shadow_mask(&reference.output.image, &unshadowed).iter().filter(|s| **s).count();
            assert!(darkened > 50, "{name}: the reference shows no shadow ({darkened} pixels)");
            for &k in increments {
                for normalize in ADDITIVE_NORMALISATIONS {
                    let options = ShadowVolumeOptions { increment: k, normalize, ..base };
                    let emulated = render_additive(&gpu, &scene, StencilMode::Emulated, options);
                    let differing = rgb_differences(&emulated.output.image, &reference.output.image);
                    let what = format!("{name} {method:?} k={k} {}", normalize.name());
                    assert_eq!(differing, 0, "{what}: {differing} pixels differ");
                    // The subpass mask counts saturation (none here: every count is far from
                    // 255/k).
                    let measured = (normalize == Normalize::Subpass).then_some(0);
                    assert_eq!(emulated.stats.saturated_samples, measured, "{what}");
                    if normalize == Normalize::Subpass {
                        // One sample: the shading pass reads the count, so the frame has the
                        // reference's passes; and on a device without fragment atomics too.
                        let passes = |f: &Frame| f.output.counters.passes.len();
                        assert_eq!(passes(&emulated), passes(&reference), "{what}: passes");
                        let uncounted = ShadowVolumeOptions { fragment_atomics: false, ..options };
                        let emulated = render_additive(&gpu, &scene, StencilMode::Emulated, uncounted);
                        let differing = rgb_differences(&emulated.output.image, &reference.output.image);
                        assert_eq!(differing, 0, "{what}, no fragment atomics: {differing} pixels differ");
                    }
                }
            }
        }
    }
    common::assert_no_validation_messages(&gpu);
}

/// Every built-in scene, z-fail and the scene's own choice, in the seed's frame (k = 1,
/// D = 102): each emulated normalisation equals the reference pixel for pixel (the subpass apply
/// counting no saturation), with volumes clipped to the receivers' bounds, the default. Clipped
/// volumes, each drawn inside its own scissor and the apply inside their union, draw the
/// unclipped image and rasterise fewer volume fragments. "The same image" up to rounding: a
/// clipped wall is another triangle in the same plane, so its depth is rounded differently where
/// it grazes a surface (a caster's own terminator, a face lying along the light), and there a
/// pixel may flip. Unclipped, the emulated seed path still equals its reference exactly:
/// clipping changes the volumes, and so the counts, not how a count is normalised, which the
/// clipped frames prove in every normalisation.
/// k and D are swept by `increment_and_darkness_change_only_the_blend_arithmetic`. (This test and
/// the every-scene k/D sweep drew the same clipped frames; they are one test now.)
#[test]
fn emulated_equals_reference_on_every_scene_clipped_or_not() {
    let gpu = common::gpu();
    let volume_fragments = |frame: &Frame| -> u64 {
        frame
            .output
            .counters
            .passes
            .iter()
            .filter(|p| p.name.starts_with("volumes"))
            .filter_map(|p| p.fragment_invocations)
            .sum()
    };
    let (mut clipped_total, mut unclipped_total, mut edge_changes) = (0, 0, 0);
    for (name, _) in BUILTIN_SCENES {
        let scene = builtin_scene(name).expect("scene");
        let unshadowed = lit(&gpu, &scene);
        for method in [VolumeMethod::Auto, VolumeMethod::ZFail] {
            let base = ShadowVolumeOptions { method, ..seed() };
            let unclipped = ShadowVolumeOptions { clip_volumes: false, ..base };
            let unclipped_reference = render(&gpu, &scene, StencilMode::Reference, unclipped);
            let clipped_reference = render(&gpu, &scene, StencilMode::Reference, base);
            let shadowed = shadow_mask(&clipped_reference.output.image, &unshadowed).iter().filter(|s| **s).count();
            assert!(shadowed > 50, "{name} {method:?}: the reference shows no shadow ({shadowed} pixels)");
            let changed = rgb_differences(&clipped_reference.output.image, &unclipped_reference.output.image);
            let shadowed = shadow_mask(&unclipped_reference.output.image, &unshadowed).iter().filter(|s| **s).count();
            assert!(
                changed * 20 <= shadowed.max(20),
                "{name} {method:?}: clipping changed {changed} of {shadowed} shadowed pixels"
            );
            edge_changes += changed as u64;
            for &normalize in Normalize::ALL {
                let emulated = render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions { normalize, ..base });
                let what = format!("{name} {method:?} {}", normalize.name());
                // Only the subpass apply counts saturation without the probe.
                let measured = (normalize == Normalize::Subpass).then_some(0);
                assert_eq!(emulated.stats.saturated_samples, measured, "{what}");
                let differing = rgb_differences(&emulated.output.image, &clipped_reference.output.image);
                assert_eq!(differing, 0, "{what}: {differing} pixels differ from the reference");
            }
            let emulated = render(&gpu, &scene, StencilMode::Emulated, unclipped);
            let differing = rgb_differences(&emulated.output.image, &unclipped_reference.output.image);
            assert_eq!(differing, 0, "{name} {method:?} unclipped: {differing} pixels differ from the reference");
            let (c, u) = (volume_fragments(&clipped_reference), volume_fragments(&unclipped_reference));
            assert!(c <= u, "{name} {method:?}: clipped volumes shade {c} fragments, unclipped {u}");
            clipped_total += c;
            unclipped_total += u;
        }
    }
    let frames = BUILTIN_SCENES.len() as u64 * 2 * u64::from(SIZE.0 * SIZE.1);
    assert!(edge_changes * 1000 < frames, "clipping changed {edge_changes} pixels of {frames}");
    assert!(clipped_total * 10 < unclipped_total * 9, "clipping saves under 10%: {clipped_total} of {unclipped_total}");
    common::assert_no_validation_messages(&gpu);
}

/// A narrow spot: its cone (widened by `CONE_MARGIN`) bounds the casters it draws volumes for
/// and the rectangle its passes draw in (Doom 3's light volume and light scissor). Every pixel
/// the spot lights lies in that rectangle; in the additive loop at 1 and 4 samples each
/// emulated normalisation equals the reference, clipping flips no pixel with the spot that it
/// does not flip without it (the grazing flips of clipped walls), and the spot's passes shade
/// under a quarter of the unclipped fragments, for fewer volumes.
#[test]
fn a_narrow_spots_cone_bounds_its_casters_and_its_passes() {
    let gpu = common::gpu();
    let base = builtin_scene("default").expect("scene");
    let mut scene = base.clone();
    let spot =
        parse_light_spec("spot:name=narrow:at=-2.5,5,2:aim=-1.6,0.8,0:inner=6:outer=10:intensity=30").expect("spot");
    scene.lights.push(spot.clone());

    let extent = vk::Extent2D { width: SIZE.0, height: SIZE.1 };
    let receivers = bounds::receivers_box(&bounds::object_boxes(&scene));
    let Scissor::Rects(rects) = bounds::light_scissor(&spot, receivers, &scene.camera, extent) else {
        panic!("a spot has a scissor rectangle")
    };
    let [rect] = rects[..] else { panic!("one rectangle: {rects:?}") };
    let (without, with) = (lit(&gpu, &base), lit(&gpu, &scene));
    let lit_by_spot: Vec<(u32, u32)> = (0..SIZE.1)
        .flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
        .filter(|&(x, y)| without.get_pixel(x, y).0[..3] != with.get_pixel(x, y).0[..3])
        .collect();
    assert!(lit_by_spot.len() > 100, "the spot lights {} pixels", lit_by_spot.len());
    let inside = |&(x, y): &(u32, u32)| {
        let (x, y) = (x as i32, y as i32);
        x >= rect.offset.x
            && y >= rect.offset.y
            && x < rect.offset.x + rect.extent.width as i32
            && y < rect.offset.y + rect.extent.height as i32
    };
    let outside: Vec<_> = lit_by_spot.iter().filter(|p| !inside(p)).collect();
    assert!(outside.is_empty(), "lit outside the spot's scissor {rect:?}: {outside:?}");
    let area = rect.extent.width * rect.extent.height;
    assert!(area * 4 < SIZE.0 * SIZE.1, "the cone's rectangle {rect:?} is a quarter of the frame or more");

    let spot_fragments = |frame: &Frame| -> u64 {
        let passes = frame.output.counters.passes.iter().filter(|p| p.name.starts_with("narrow:"));
        passes.filter_map(|p| p.fragment_invocations).sum()
    };
    let spot_volumes = |frame: &Frame| {
        let report = frame.stats.lights.iter().find(|l| l.name == "narrow");
        report.expect("the spot is reported").volumes
    };
    for samples in [1, 4] {
        let frame_of_scene = |scene: &Scene, stencil, normalize, clip_volumes| {
            let options = ShadowVolumeOptions { normalize, clip_volumes, ..seed() };
            let options = RenderOptions {
                samples,
                ..render_options(stencil, ShadowMode::Additive, options, SIZE, ShadowTone::default())
            };
            frame_of(&gpu, scene, &options).expect("shadow-volume frame")
        };
        let frame = |stencil, normalize, clip_volumes| frame_of_scene(&scene, stencil, normalize, clip_volumes);
        let reference = frame(StencilMode::Reference, Normalize::Seed, true);
        for &normalize in Normalize::ALL {
            let emulated = frame(StencilMode::Emulated, normalize, true);
            let differing = rgb_differences(&emulated.output.image, &reference.output.image);
            assert_eq!(differing, 0, "{samples}x {}: {differing} pixels differ from the reference", normalize.name());
        }
        // Clipping flips a grazing pixel now and then (`emulated_equals_reference_on_every_scene_clipped_or_not`):
        // with the spot, it flips none that it does not flip without it.
        let unclipped = frame(StencilMode::Reference, Normalize::Seed, false);
        let base_frame =
            |clip_volumes| frame_of_scene(&base, StencilMode::Reference, Normalize::Seed, clip_volumes).output.image;
        let (base_clipped, base_unclipped) = (base_frame(true), base_frame(false));
        let flipped = |a: &RgbaImage, b: &RgbaImage| -> HashSet<usize> {
            let pixels = a.chunks_exact(4).zip(b.chunks_exact(4)).enumerate();
            pixels.filter(|(_, (p, q))| p[..3] != q[..3]).map(|(i, _)| i).collect()
        };
        let with_spot = flipped(&reference.output.image, &unclipped.output.image);
        let without = flipped(&base_clipped, &base_unclipped);
        let added: Vec<_> = with_spot.difference(&without).collect();
        assert!(added.is_empty(), "{samples}x: with the spot, clipping flips pixels {added:?}");
        let (clipped, whole) = (spot_fragments(&reference), spot_fragments(&unclipped));
        assert!(clipped * 4 < whole, "{samples}x: the spot's passes shade {clipped} fragments, unclipped {whole}");
        let (drawn, all) = (spot_volumes(&reference), spot_volumes(&unclipped));
        assert!(drawn < all, "{samples}x: the spot drew {drawn} volumes, unclipped {all}");
    }
    common::assert_no_validation_messages(&gpu);
}

/// Casters wholly in the shadow of other casters cast nothing new (CC Shadow Volumes' culling,
/// docs/shadow-volumes.md "Casters culled"): with culling on and off the reference draws the same
/// image, on every built-in scene and on a nested one, in both modes and both counting methods;
/// culling never raises the volumes' fragments, and on the nested scene it culls both boxes and
/// saves fragments. Where culling culls a caster (the nested scene), every emulated
/// normalisation equals the culled reference, at 1 and 4 samples. Where it culls none, the
/// culled frame draws the unculled volumes, whose emulated frames equal the reference in every
/// normalisation at 1x in `emulated_equals_reference_on_every_scene_clipped_or_not` and
/// `additive_emulated_equals_reference_on_every_scene`, and at 4x in tests/inside/plan.rs.
/// (Every case once drew all five frames at both sample counts: 520 frames, 41 s.)
#[test]
fn culled_casters_draw_the_unculled_image_with_fewer_fragments() {
    let gpu = common::gpu();
    let volume_fragments = |frame: &Frame| -> u64 {
        let passes = frame.output.counters.passes.iter();
        passes.filter(|p| p.name.contains("volumes")).filter_map(|p| p.fragment_invocations).sum()
    };
    let frame = |scene: &Scene, stencil, (options, shadow_mode): (ShadowVolumeOptions, ShadowMode), samples| {
        let options = RenderOptions {
            width: SIZE.0,
            height: SIZE.1,
            stencil,
            technique: technique("shadow-volume"),
            shadow_volume: options,
            shadow_mode,
            samples,
            ..Default::default()
        };
        let frame = render_scene(&gpu, scene, &options).expect("shadow-volume frame");
        let stats = frame.stats::<nostencil::stats::ShadowVolumeStats>().expect("statistics").clone();
        Frame { output: frame.output, stats }
    };
    let mut scenes: Vec<(String, Scene)> =
        BUILTIN_SCENES.iter().map(|(name, _)| (name.to_string(), builtin_scene(name).expect("scene"))).collect();
    scenes.push(("nested".into(), nested_scene()));
    let mut nested_culled = None;
    let mut culling_cases = 0;
    for (name, scene) in &scenes {
        for mode in [ShadowMode::Additive, ShadowMode::Modulate] {
            for method in [VolumeMethod::Auto, VolumeMethod::ZFail] {
                let mut culls = false;
                for samples in [1, 4] {
                    if samples == 4 && !culls {
                        continue;
                    }
                    let base = ShadowVolumeOptions { method, ..Default::default() };
                    let what = format!("{name} {mode:?} {method:?} {samples}x");
                    let unculled = frame(scene, StencilMode::Reference, (base, mode), samples);
                    let base = ShadowVolumeOptions { cull_casters: true, ..base };
                    let culled = frame(scene, StencilMode::Reference, (base, mode), samples);
                    let differing = rgb_differences(&culled.output.image, &unculled.output.image);
                    assert_eq!(differing, 0, "{what}: culling changed {differing} pixels of the reference");
                    let culled_casters: usize = culled.stats.lights.iter().map(|l| l.culled).sum();
                    assert!(unculled.stats.lights.iter().all(|l| l.culled == 0), "{what}: culled with culling off");
                    culls = culled_casters > 0;
                    culling_cases += usize::from(culls);
                    // Where nothing is culled the emulated frame draws the unculled volumes.
                    let normalisations = if culls { Normalize::ALL } else { &[][..] };
                    for &normalize in normalisations {
                        let emulated = frame(
                            scene,
                            StencilMode::Emulated,
                            (ShadowVolumeOptions { normalize, ..base }, mode),
                            samples,
                        );
                        let differing = rgb_differences(&emulated.output.image, &culled.output.image);
                        assert_eq!(
                            differing,
                            0,
                            "{what} {}: {differing} pixels differ from the reference",
                            normalize.name()
                        );
                    }
                    let (c, u) = (volume_fragments(&culled), volume_fragments(&unculled));
                    assert!(c <= u, "{what}: culled volumes shade {c} fragments, unculled {u}");
                    if name == "nested" && samples == 1 && method == VolumeMethod::Auto && mode == ShadowMode::Modulate
                    {
                        nested_culled = Some((culled_casters, c, u));
                    }
                }
            }
        }
    }
    let (casters, culled, unculled) = nested_culled.expect("the nested scene was rendered");
    assert_eq!(casters, 2, "the nested scene's two boxes lie in the roof's shadow");
    assert!(culled < unculled, "culling two boxes saved no fragments: {culled} of {unculled}");
    eprintln!("culling culled casters in {culling_cases} of the cases (scene, mode, method, samples)");
    assert!(culling_cases >= 8, "culling culled casters in only {culling_cases} cases");
    common::assert_no_validation_messages(&gpu);
}

/// Each near cap of an open caster drawn only by the counting pipeline that can see it past its
/// own face (docs/shadow-volumes.md, "Near caps under their faces"): on every built-in scene of
/// open casters, in both modes and at 1 and 4 samples, the frame is the one with every near cap
/// drawn by both pipelines (`--whole-near-caps`) and the reference's, for less vertex and
/// primitive work and no more fragments; z-fail, whose near caps count at their faces' own
/// depth, draws them all. Every normalisation is drawn in the modulate mode at 1x; elsewhere the
/// seed path alone: which pipeline draws a near cap changes the volumes, and so the counts, not
/// how a count is normalised (every normalisation of these scenes' counts, split near caps being
/// the default, is `emulated_equals_reference_on_every_scene_clipped_or_not`'s and
/// `additive_emulated_equals_reference_on_every_scene`'s at 1x, tests/inside/plan.rs's at 4x).
#[test]
fn near_caps_left_to_the_pipeline_that_sees_them_draw_the_whole_image_for_less_work() {
    let gpu = common::gpu();
    let whole_caps = ShadowVolumeOptions { split_near_caps: false, ..seed() };
    for name in ["open-quad", "open-box", "non-manifold", "touching"] {
        let scene = builtin_scene(name).expect("scene");
        for mode in [ShadowMode::Additive, ShadowMode::Modulate] {
            for samples in [1, 4] {
                let frame = |stencil, options| {
                    let options = render_options(stencil, mode, options, SIZE, ShadowTone::default());
                    frame_of(&gpu, &scene, &RenderOptions { samples, ..options }).expect("shadow-volume frame")
                };
                let what = format!("{name} {mode:?} {samples}x");
                let reference = frame(StencilMode::Reference, seed());
                let whole = frame(StencilMode::Emulated, whole_caps);
                let differing = rgb_differences(&whole.output.image, &reference.output.image);
                assert_eq!(differing, 0, "{what}: whole near caps differ from the reference at {differing} pixels");
                let every = mode == ShadowMode::Modulate && samples == 1;
                let normalisations = if every { Normalize::ALL } else { &[Normalize::Seed][..] };
                for &normalize in normalisations {
                    let split = frame(StencilMode::Emulated, ShadowVolumeOptions { normalize, ..seed() });
                    let differing = rgb_differences(&split.output.image, &reference.output.image);
                    let what = format!("{what} {}", normalize.name());
                    assert_eq!(differing, 0, "{what}: split near caps differ from the reference at {differing} pixels");
                    let ([sv, sp, sf], [wv, wp, wf]) = (volume_work(&split), volume_work(&whole));
                    assert!(sv <= wv && sp < wp, "{what}: vertices {sv} of {wv}, primitives {sp} of {wp}");
                    assert!(sf <= wf, "{what}: split near caps shade {sf} fragments, whole ones {wf}");
                    let one_pipeline =
                        |frame: &Frame| frame.stats.lights.iter().map(|l| l.near_caps_one_pipeline).sum();
                    let (split_caps, whole_caps): (u64, u64) = (one_pipeline(&split), one_pipeline(&whole));
                    assert!(split_caps > 0 && whole_caps == 0, "{what}: near caps split {split_caps}, {whole_caps}");
                }
            }
        }
        let zfail = ShadowVolumeOptions { method: VolumeMethod::ZFail, ..seed() };
        let split = render(&gpu, &scene, StencilMode::Emulated, zfail);
        let whole =
            render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions { split_near_caps: false, ..zfail });
        assert_eq!(volume_work(&split), volume_work(&whole), "{name}: z-fail's near caps were split");
        assert_eq!(rgb_differences(&split.output.image, &whole.output.image), 0, "{name}: z-fail");
    }
    common::assert_no_validation_messages(&gpu);
}

/// Seed 000's apply modulates with a shadow colour: `--shadow-colour` tints the shadow in every
/// path, each still equal to the reference pixel for pixel, and a shadowed pixel is its lit
/// colour times the tint, channel by channel (in linear light, where the blend multiplies).
#[test]
fn a_tinted_shadow_is_the_references_in_every_path_and_multiplies_each_channel() {
    let gpu = common::gpu();
    let scene = builtin_scene("box").expect("scene");
    let unshadowed = lit(&gpu, &scene);
    // Three factors, two equal ones, and a grey given as a colour (it must match --shadow-factor).
    for tint in [[51u8, 128, 204], [200, 90, 200], [102, 102, 102]] {
        let base = seed();
        let tone = ShadowTone::Tinted(tint);
        let reference = render_toned(&gpu, &scene, StencilMode::Reference, base, tone);
        for &normalize in Normalize::ALL {
            for k in [1u8, 4] {
                let options = ShadowVolumeOptions { normalize, increment: k, ..base };
                let emulated = render_toned(&gpu, &scene, StencilMode::Emulated, options, tone);
                let differing = rgb_differences(&emulated.output.image, &reference.output.image);
                assert_eq!(differing, 0, "tint {tint:?}, {} k={k}: {differing} pixels differ", normalize.name());
            }
        }
        let mut checked = 0;
        for (shadowed, lit) in reference.output.image.pixels().zip(unshadowed.pixels()) {
            if shadowed.0[..3] == lit.0[..3] {
                continue;
            }
            for c in 0..3 {
                let expected = common::srgb_encode(common::srgb_decode(lit.0[c]) * f32::from(tint[c]) / 255.0);
                assert!(shadowed.0[c].abs_diff(expected) <= 1, "tint {tint:?}: {shadowed:?} from {lit:?}");
            }
            checked += 1;
        }
        assert!(checked > 100, "tint {tint:?}: only {checked} shadowed pixels");
    }
    // A grey tint is --shadow-factor.
    let options = ShadowVolumeOptions::default();
    let (a, b) = (
        render_toned(&gpu, &scene, StencilMode::Emulated, options, ShadowTone::Tinted([102; 3])),
        render_toned(&gpu, &scene, StencilMode::Emulated, options, ShadowTone::Grey(102)),
    );
    assert_eq!(rgb_differences(&a.output.image, &b.output.image), 0);
    assert_eq!(pass_names(&a), pass_names(&b), "a grey tint draws the grey plan");
    common::assert_no_validation_messages(&gpu);
}
