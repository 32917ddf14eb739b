//! The alpha counter's arithmetic against hand-computed answers: the normalisation table read
//! back from the GPU, the iteration counts, saturation counted by the subpass apply, the
//! reference's passes, the shadow factor, and the seed's own pass list.

use super::*;

/// docs/design/blend-rounding.md: at D = 102 and k = 4 three iterations bring every shadowed count to
/// <= D on any GPU (reaching 0 under lavapipe's rounding took four), and the image is still the
/// reference's.
#[test]
fn seed_path_runs_three_iterations_at_d_102_and_k_4() {
    let gpu = common::gpu();
    let scene = builtin_scene("default").expect("scene");
    let options = ShadowVolumeOptions { increment: 4, normalize: Normalize::Seed, ..seed() };
    let emulated = render(&gpu, &scene, StencilMode::Emulated, options);
    let reference = render(&gpu, &scene, StencilMode::Reference, options);
    assert_eq!(emulated.stats.seed_iterations, 3);
    let normalising: Vec<&str> = emulated
        .output
        .counters
        .passes
        .iter()
        .map(|p| p.name.as_str())
        .filter(|n| n.starts_with("normalise"))
        .collect();
    assert_eq!(normalising, ["normalise N0", "normalise N1", "normalise N2", "normalise N3"]);
    let shadowed = shadow_mask(&reference.output.image, &lit(&gpu, &scene)).iter().filter(|s| **s).count();
    assert!(shadowed > 500, "the default scene shows {shadowed} shadowed pixels");
    assert_eq!(rgb_differences(&emulated.output.image, &reference.output.image), 0);
    common::assert_no_validation_messages(&gpu);
}

/// Writes every alpha value 0..=255 into a 16x16 frame, value `i` at pixel (i % 16, i / 16),
/// each by a one-pixel clear (grey colour, alpha `i/255`: float-to-UNORM rounds to nearest).
fn write_every_alpha(rec: &mut FrameRecorder) {
    for i in 0..=255u32 {
        let clear = vk::ClearAttachment {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            color_attachment: 0,
            clear_value: vk::ClearValue { color: vk::ClearColorValue { float32: [0.5, 0.5, 0.5, i as f32 / 255.0] } },
        };
        let rect = vk::ClearRect {
            rect: vk::Rect2D {
                offset: vk::Offset2D { x: (i % 16) as i32, y: (i / 16) as i32 },
                extent: vk::Extent2D { width: 1, height: 1 },
            },
            base_array_layer: 0,
            layer_count: 1,
        };
        // SAFETY: recorded inside the frame's render pass (the recorder's closure), whose colour
        // attachment 0 covers the 16x16 rect; the command buffer is recording.
        unsafe { rec.device().cmd_clear_attachments(rec.cmd, &[clear], &[rect]) };
    }
}

/// The model of a normalisation pass, found by its pipeline.
fn model_step<K: PassKinds>(pass: &PlannedPass<K>) -> alpha_counter::Step {
    use alpha_counter::Step;
    match pass.pipeline().map(|d| d.name) {
        Some("normalise N0") => Step::N0,
        Some("normalise iteration") => Step::Iteration,
        Some("darkness subtract D") => Step::SubtractD,
        Some("darkness add D") => Step::AddD,
        Some("darkness max D") => Step::MaxD,
        other => panic!("pass '{}' ({other:?}) is not a normalisation step", pass.name),
    }
}

#[test]
fn normalisation_table_is_read_back_from_the_gpu() {
    // docs/design/lavapipe.md: with k = 1 a count of 1 reads 253, 249, 237, 202, 107, 0 after N0 and each
    // iteration, under lavapipe's rounding.
    assert_eq!(alpha_counter::seed_sequence(1), [253u8, 249, 237, 202, 107, 0]);
    let gpu = common::gpu();
    let uniforms = common::clip_space_uniforms();
    let mut renderer = Renderer::new(&gpu, 16, 16, StencilMode::Emulated, false).expect("renderer");
    // On the format the frame ships in: alpha is linear UNORM8 there, the colour sRGB.
    assert_eq!(renderer.targets.desc.colour.format, COLOUR_FORMAT);
    assert_eq!(COLOUR_FORMAT, ash::vk::Format::R8G8B8A8_SRGB);
    let grey = common::srgb_encode(0.5);
    let mut pipelines: HashMap<&'static str, Pipeline> = HashMap::new();
    let mut checked: HashSet<Vec<(alpha_counter::Step, u8)>> = HashSet::new();
    let cases = [(1u8, 102u8), (4, 102), (4, 64), (2, 64), (8, 128), (2, 0), (8, 192)];
    for (k, d) in cases {
        for normalize in [Normalize::Seed, Normalize::Max] {
            // The plan's normalisation passes for this k and D: N0 up to the apply.
            let options =
                ShadowVolumeOptions { increment: k, normalize, method: VolumeMethod::ZPass, ..Default::default() };
            let plan = shadow_volume::recipes::plan(
                &options,
                nostencil::ShadowMode::Modulate,
                ShadowTone::Grey(d),
                StencilMode::Emulated,
                1,
                &nostencil::technique::light_loop::PlannedLight::default_lights(),
            )
            .expect("plan");
            let first = plan.passes.iter().position(|p| p.name == "normalise N0").expect("N0 in the plan");
            let last = plan.passes.iter().position(|p| p.name == "apply").expect("apply in the plan");
            let steps = &plan.passes[first..last];
            let n = alpha_counter::seed_iterations(k, d).expect("iterations");
            assert_eq!(steps.iter().filter(|p| model_step(p) == alpha_counter::Step::Iteration).count(), n);
            for pass in steps {
                let desc = pass.pipeline().expect("a full-screen pipeline");
                if !pipelines.contains_key(desc.name) {
                    let pipeline =
                        Pipeline::new(&gpu, desc, renderer.targets.render_pass, &[]).expect("normalisation pipeline");
                    pipelines.insert(desc.name, pipeline);
                }
            }
            // Read the alpha back after each step, for every alpha value at once.
            for length in 1..=steps.len() {
                let prefix = &steps[..length];
                let key: Vec<_> = prefix.iter().map(|p| (model_step(p), d)).collect();
                if !checked.insert(key.clone()) {
                    continue;
                }
                let output = renderer
                    .render(&uniforms, [0.5, 0.5, 0.5, 0.0], |rec| {
                        write_every_alpha(rec);
                        for pass in prefix {
                            let pipeline = &pipelines[pass.pipeline().map_or("", |d| d.name)];
                            let Draws::FullScreen { push: Some(value) } = pass.draws else {
                                panic!("'{}' has no constant", pass.name)
                            };
                            rec.pass(&pass.name, |rec| {
                                rec.bind(pipeline);
                                rec.push(pipeline, &value);
                                rec.draw(3, 1, 0, 0);
                                Ok(())
                            })?;
                        }
                        Ok(())
                    })
                    .expect("frame");
                let model = |start: u8| {
                    key.iter().fold(start, |a, &(step, d)| step.apply(a, d, alpha_counter::Rounding::Lavapipe))
                };
                for i in 0..=255u8 {
                    let pixel = output.image.get_pixel(i as u32 % 16, i as u32 / 16).0;
                    assert_eq!(
                        pixel[3],
                        model(i),
                        "k = {k}, D = {d}, {}: alpha {i} after {}",
                        normalize.name(),
                        prefix.iter().map(|p| p.name.as_ref()).collect::<Vec<_>>().join(", ")
                    );
                    assert_eq!(pixel[..3], [grey; 3], "the normalisation writes alpha only");
                }
                // After the last step: lit pixels at 1, every shadowed count at exactly D.
                if length == steps.len() {
                    let alpha = |i: u32| output.image.get_pixel(i % 16, i / 16).0[3];
                    assert_eq!(alpha(0), 255, "k = {k}, D = {d}: a lit pixel");
                    for count in 1..=alpha_counter::capacity(k) {
                        assert_eq!(alpha(count * k as u32), d, "k = {k}, D = {d}: a count of {count}");
                    }
                }
            }
        }
    }
    assert!(checked.len() > 20, "{} prefixes read back", checked.len());
    common::assert_no_validation_messages(&gpu);
}

fn stack_scene(boxes: usize) -> Scene {
    let mut scene = builtin_scene("box").expect("scene");
    scene.objects.retain(|o| o.name == "ground");
    scene.set_light(nostencil::Light::Directional { direction: Vec3::NEG_Y });
    let cube = scene.add_mesh("thin box", nostencil::mesh::shapes::cube(1.0));
    for i in 0..boxes {
        let transform = Mat4::from_scale_rotation_translation(
            Vec3::new(1.5, 0.05, 1.5),
            glam::Quat::IDENTITY,
            Vec3::new(0.0, 0.5 + 0.1 * i as f32, 0.0),
        );
        scene.add_object(&format!("layer {i}"), cube, transform, Vec3::ONE, true);
    }
    scene
}

/// docs/design/saturation.md: saturation (the counter at its clamp once every volume is drawn) is
/// counted by the subpass apply's atomic add, with no probe pass; the opt-in probe on the same
/// frame counts the same pixels.
#[test]
fn the_subpass_apply_counts_saturation_with_no_probe_and_matches_the_probe() {
    let gpu = common::gpu();
    // 40 stacked layers: seen from the camera, ground pixels under the stack sit inside up to 40
    // volumes. k = 8 holds 31, k = 1 holds 255.
    let scene = stack_scene(40);
    let subpass = |increment, saturation_probe| ShadowVolumeOptions {
        increment,
        normalize: Normalize::Subpass,
        saturation_probe,
        ..seed()
    };
    let k8 = render(&gpu, &scene, StencilMode::Emulated, subpass(8, false));
    assert_eq!(k8.stats.capacity, 31);
    let names = pass_names(&k8);
    assert!(!names.contains(&shadow_volume::SATURATION_PROBE), "no probe pass by default: {names:?}");
    let full_screen = k8.output.counters.passes.iter().filter(|p| p.name.starts_with("apply")).count();
    assert_eq!(full_screen, 1, "{names:?}");
    let counted = k8.stats.saturated_samples.expect("the subpass apply counts saturation");
    let pixels = u64::from(SIZE.0 * SIZE.1);
    assert!(counted > 50 && counted < pixels / 2, "k = 8 with 40 stacked volumes: {counted} saturated pixels");
    assert_eq!(k8.stats.probe_saturated_samples, None);

    // The same frame with the probe: both count the same pixels.
    let both = render(&gpu, &scene, StencilMode::Emulated, subpass(8, true));
    assert!(pass_names(&both).contains(&shadow_volume::SATURATION_PROBE));
    assert_eq!(both.stats.probe_saturated_samples, both.stats.saturated_samples, "apply and probe disagree");
    assert_eq!(both.stats.saturated_samples, Some(counted), "the probe changed the apply's count");

    // The blend-only paths count only with the probe, and find the same pixels.
    let seed = ShadowVolumeOptions { increment: 8, ..seed() };
    let unmeasured = render(&gpu, &scene, StencilMode::Emulated, seed);
    assert_eq!(unmeasured.stats.saturated_samples, None);
    assert!(!pass_names(&unmeasured).contains(&shadow_volume::SATURATION_PROBE));
    assert!(unmeasured.stats.saturation_measured_by.contains("--saturation-probe"));
    let probed = render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions { saturation_probe: true, ..seed });
    assert_eq!(probed.stats.saturated_samples, Some(counted));

    // Without fragment atomics (a device outside the baseline) the subpass path says so, and
    // draws the same image.
    let without = ShadowVolumeOptions { fragment_atomics: false, ..subpass(8, false) };
    let uncounted = render(&gpu, &scene, StencilMode::Emulated, without);
    assert_eq!(uncounted.stats.saturated_samples, None);
    assert!(uncounted.stats.saturation_measured_by.contains("fragmentStoresAndAtomics"));
    assert_eq!(rgb_differences(&uncounted.output.image, &k8.output.image), 0);

    // Not vacuous: k = 1 holds 40 volumes, so nothing saturates.
    let k1 = render(&gpu, &scene, StencilMode::Emulated, subpass(1, false));
    assert_eq!(k1.stats.capacity, 255);
    assert_eq!(k1.stats.saturated_samples, Some(0));
    common::assert_no_validation_messages(&gpu);
}

/// The reference a port would ship: volumes and one stencil-tested apply. Negative counts (a
/// z-pass camera inside a volume leaves -1 behind its exit wall) stay lit, as the clamping
/// alpha counter leaves them, so emulated z-pass still equals the reference there, wrong as
/// both images are.
#[test]
fn the_reference_is_volumes_and_one_apply_and_leaves_negative_counts_lit() {
    let gpu = common::gpu();
    let scene = builtin_scene("inside").expect("scene");
    let zpass = ShadowVolumeOptions { method: VolumeMethod::ZPass, ..seed() };
    let reference = render(&gpu, &scene, StencilMode::Reference, zpass);
    let names = pass_names(&reference);
    assert_eq!(names, ["scene", "volumes (stencil, z-pass)", "apply (stencil)"], "{names:?}");
    for &normalize in Normalize::ALL {
        let emulated = render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions { normalize, ..zpass });
        let differing = rgb_differences(&emulated.output.image, &reference.output.image);
        assert_eq!(differing, 0, "z-pass inside a volume, {}: {differing} pixels differ", normalize.name());
    }
    // Not vacuous: behind the exit wall the z-pass count is -1. A reference that shaded every
    // non-zero count (NOT_EQUAL 0, no bias) would darken pixels there that the correct z-fail
    // image leaves lit; this one darkens none.
    let zfail =
        render(&gpu, &scene, StencilMode::Reference, ShadowVolumeOptions { method: VolumeMethod::ZFail, ..zpass });
    let unshadowed = lit(&gpu, &scene);
    let zpass_dark = shadow_mask(&reference.output.image, &unshadowed);
    let zfail_dark = shadow_mask(&zfail.output.image, &unshadowed);
    let wrongly_dark = zpass_dark.iter().zip(&zfail_dark).filter(|(p, f)| **p && !**f).count();
    assert_eq!(wrongly_dark, 0, "z-pass reference darkens {wrongly_dark} pixels z-fail leaves lit");
    common::assert_no_validation_messages(&gpu);
}

/// `--shadow-factor F` darkens shadow volumes to F/255 (in linear light: the frame is sRGB) in
/// every path, and the seed and max paths' iteration count follows it.
#[test]
fn the_command_line_sets_the_shadow_factor_and_the_iterations_follow_it() {
    let dir = common::scratch_dir("shadow-volume-factor");
    let render = |name: &str, args: &[&str]| {
        let out = dir.join(name);
        let out = out.to_str().expect("a UTF-8 path");
        // One sample: every darkened pixel is then wholly in shadow (4x blends the borders).
        // The seed's frame, whose shadow the factor darkens.
        let mut all = vec!["render", "--size", "128x96", "--samples", "1", "--shadow-mode", "modulate", "--out", out];
        all.extend_from_slice(args);
        common::run_ok(&all);
        common::read_png(Path::new(out))
    };
    let lit = render("lit.png", &["--technique", "lit"]);
    for factor in [51u8, 204] {
        let f = factor.to_string();
        let reference = render("reference.png", &["--shadow-factor", &f, "--stencil", "reference"]);
        let mut darkened = 0;
        for (p, q) in reference.pixels().zip(lit.pixels()) {
            if p != q {
                let want = q.0.map(|c| common::srgb_encode(common::srgb_decode(c) * factor as f32 / 255.0));
                assert!(common::near(&p.0, &want, 1), "F = {factor}: {p:?}, lit {q:?} x F/255 = {want:?}");
                darkened += 1;
            }
        }
        assert!(darkened > 300, "F = {factor}: {darkened} pixels darkened");
        for normalize in ["seed", "max", "subpass"] {
            let emulated =
                render("emulated.png", &["--shadow-factor", &f, "--normalize", normalize, "--increment", "4"]);
            assert!(emulated == reference, "F = {factor}, {normalize}: emulated differs from the reference");
        }
    }
    // k = 4: D = 64 needs four iterations when products round up, D = 102 three.
    for (factor, iterations) in [("64", 4), ("102", 3)] {
        let args = [
            "--technique",
            "shadow-volume",
            "--shadow-mode",
            "modulate",
            "--normalize",
            "max",
            "--increment",
            "4",
            "--shadow-factor",
            factor,
        ];
        let (passes, _) = common::run_ok(&[&["passes"], &args[..]].concat());
        assert!(passes.contains(&format!("normalise N{iterations} ")), "D = {factor}:\n{passes}");
        assert!(!passes.contains(&format!("normalise N{} ", iterations + 1)), "D = {factor}:\n{passes}");
        let (json, _) = common::run_ok(&[&["profile", "--size", "64x48", "--format", "json"], &args[..]].concat());
        let report: serde_json::Value = serde_json::from_str(&json).expect("JSON");
        assert_eq!(report["technique_stats"]["seed_iterations"], iterations, "D = {factor}");
        let names: Vec<&str> =
            report["passes"].as_array().expect("passes").iter().filter_map(|p| p["name"].as_str()).collect();
        assert!(names.contains(&format!("normalise N{iterations}").as_str()), "D = {factor}: {names:?}");
        assert!(!names.contains(&format!("normalise N{}", iterations + 1).as_str()), "D = {factor}: {names:?}");
    }
}

/// Seed 000 counts its method as "6 build steps, 2 normalisation steps, 1 apply step" with
/// four iterations after N0 (its table's steps 2..5). Our seed path for k = 1 is that list
/// whenever four iterations are enough when products round up, i.e. for D >= 139 (a count of
/// one then ends at 139): after the scene, the volume pass (the table's initial count), N0 and
/// N1..N4 build the mask, "darkness subtract D" and "darkness add D" normalise it, one apply.
/// Below that D a port needs a fifth iteration, which the seed's real-number table does not
/// show (its 0.4312 is 110/255, but rounding up leaves 139).
#[test]
fn the_seed_path_for_k_1_is_the_seeds_own_pass_list() {
    assert_eq!(alpha_counter::seed_iterations(1, 139).expect("k = 1"), 4);
    assert_eq!(alpha_counter::seed_iterations(1, 138).expect("k = 1"), 5);
    let options = ShadowVolumeOptions {
        increment: 1,
        normalize: Normalize::Seed,
        method: VolumeMethod::ZPass,
        ..Default::default()
    };
    let plan = shadow_volume::recipes::plan(
        &options,
        nostencil::ShadowMode::Modulate,
        ShadowTone::Grey(192),
        StencilMode::Emulated,
        1,
        &nostencil::technique::light_loop::PlannedLight::default_lights(),
    )
    .expect("plan");
    let names: Vec<&str> = plan.passes.iter().map(|p| p.name.as_ref()).collect();
    let build =
        ["volumes (alpha, z-pass)", "normalise N0", "normalise N1", "normalise N2", "normalise N3", "normalise N4"];
    let normalisation = ["darkness subtract D", "darkness add D"];
    let expected: Vec<&str> = ["scene"].into_iter().chain(build).chain(normalisation).chain(["apply"]).collect();
    assert_eq!(names, expected);
    // The frame draws exactly that list, and it is the reference's image.
    let gpu = common::gpu();
    let scene = builtin_scene("default").expect("scene");
    let emulated = render_toned(&gpu, &scene, StencilMode::Emulated, options, ShadowTone::Grey(192));
    assert_eq!(pass_names(&emulated), expected);
    let reference = render_toned(&gpu, &scene, StencilMode::Reference, options, ShadowTone::Grey(192));
    assert_eq!(rgb_differences(&emulated.output.image, &reference.output.image), 0);
    common::assert_no_validation_messages(&gpu);
}
