//! Shadow volumes in alpha are proven against the real stencil, pixel for pixel, and against
//! hand-computed answers: the seed's normalisation table, a box's projected outline, a camera
//! inside a volume, and the background behind a volume.

use crate::common::{self, technique};

use std::collections::{HashMap, HashSet};
use std::path::Path;
use std::sync::Arc;

use ash::vk;

use glam::{Mat4, Vec3};
use image::RgbaImage;
use nostencil::frame::render_pass::COLOUR_FORMAT;
use nostencil::mesh::MeshData;
use nostencil::render::plan::Scissor;
use nostencil::render::plan::{Draws, PassKinds, PlannedPass};
use nostencil::render::FrameRecorder;
use nostencil::render::Pipeline;
use nostencil::render::Renderer;
use nostencil::scene::lights::parse_light_spec;
use nostencil::technique::shadow_volume::bounds;
use nostencil::technique::shadow_volume::{self, Normalize, ShadowVolumeOptions, VolumeMethod};
use nostencil::technique::{alpha_counter, ShadowTone};
use nostencil::Gpu;
use nostencil::StencilMode;
use nostencil::{builtin_scene, Light, Scene, BUILTIN_SCENES};
use nostencil::{render_scene, RenderOptions, ShadowMode};

const SIZE: (u32, u32) = (128, 96);

/// The family's options for the seed's frame (Hall's apply, `--shadow-mode modulate`), what most
/// proofs here are about: `render` and its siblings draw that frame. The additive loop's own
/// proofs are `additive_*` below (`render_additive`) and in tests/inside/lights.rs.
fn seed() -> ShadowVolumeOptions {
    ShadowVolumeOptions::default()
}

/// A shadow-volume frame with the technique's statistics.
struct Frame {
    output: nostencil::FrameOutput,
    stats: nostencil::stats::ShadowVolumeStats,
}

fn render(gpu: &Arc<Gpu>, scene: &Scene, stencil: StencilMode, options: ShadowVolumeOptions) -> Frame {
    render_sized(gpu, scene, stencil, options, SIZE)
}

/// `render` in the additive loop.
fn render_additive(gpu: &Arc<Gpu>, scene: &Scene, stencil: StencilMode, options: ShadowVolumeOptions) -> Frame {
    try_render(gpu, scene, stencil, ShadowMode::Additive, options, SIZE, ShadowTone::default())
        .expect("shadow-volume frame")
}

/// `render` with a shadow tone other than the default.
fn render_toned(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    options: ShadowVolumeOptions,
    shadow_tone: ShadowTone,
) -> Frame {
    try_render(gpu, scene, stencil, ShadowMode::Modulate, options, SIZE, shadow_tone).expect("shadow-volume frame")
}

fn render_sized(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    options: ShadowVolumeOptions,
    size: (u32, u32),
) -> Frame {
    try_render(gpu, scene, stencil, ShadowMode::Modulate, options, size, ShadowTone::default())
        .expect("shadow-volume frame")
}

fn try_render(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    shadow_mode: ShadowMode,
    options: ShadowVolumeOptions,
    size: (u32, u32),
    shadow_tone: ShadowTone,
) -> nostencil::Result<Frame> {
    frame_of(gpu, scene, &render_options(stencil, shadow_mode, options, size, shadow_tone))
}

fn render_options(
    stencil: StencilMode,
    shadow_mode: ShadowMode,
    options: ShadowVolumeOptions,
    size: (u32, u32),
    shadow_tone: ShadowTone,
) -> RenderOptions {
    RenderOptions {
        width: size.0,
        height: size.1,
        stencil,
        technique: technique("shadow-volume"),
        shadow_volume: options,
        shadow_mode,
        shadow_tone,
        ..Default::default()
    }
}

fn frame_of(gpu: &Arc<Gpu>, scene: &Scene, options: &RenderOptions) -> nostencil::Result<Frame> {
    let frame = render_scene(gpu, scene, options)?;
    let stats = frame.stats::<nostencil::stats::ShadowVolumeStats>().expect("shadow-volume statistics").clone();
    Ok(Frame { output: frame.output, stats })
}

fn lit(gpu: &Arc<Gpu>, scene: &Scene) -> RgbaImage {
    lit_sized(gpu, scene, SIZE)
}

fn lit_sized(gpu: &Arc<Gpu>, scene: &Scene, size: (u32, u32)) -> RgbaImage {
    let options = RenderOptions { width: size.0, height: size.1, technique: technique("lit"), ..Default::default() };
    render_scene(gpu, scene, &options).expect("lit frame").output.image
}

/// Pixels whose RGB differ (alpha holds each path's working state and is not the image).
fn rgb_differences(a: &RgbaImage, b: &RgbaImage) -> usize {
    a.chunks_exact(4).zip(b.chunks_exact(4)).filter(|(p, q)| p[..3] != q[..3]).count()
}

/// Pixels darkened by the shadow: where the shadowed frame differs from the unshadowed one.
fn shadow_mask(shadowed: &RgbaImage, lit: &RgbaImage) -> Vec<bool> {
    shadowed.chunks_exact(4).zip(lit.chunks_exact(4)).map(|(p, q)| p[..3] != q[..3]).collect()
}

/// The shadow factors of the k/D sweep: the default 102, and 64 and 128, where the
/// normalisation needs a different number of iterations (docs/design/blend-rounding.md).
const SWEEP_DARKNESS: [u8; 3] = [64, 102, 128];

/// k and D change only the blend arithmetic of the count and its normalisation, not which
/// pixels a volume covers: on the `overlap` scene (stacked casters, the deepest counts of the
/// built-in scenes), z-fail and the scene's own choice, every k in {1, 2, 4, 8} and D in
/// {64, 102, 128} in every normalisation equals the reference pixel for pixel (the subpass
/// apply counts no saturation). Every scene's geometry is proven at k = 1, D = 102 by
/// `emulated_equals_reference_on_every_scene_clipped_or_not`; every count's normalisation at
/// seven (k, D), read back from the GPU, by `normalisation_table_is_read_back_from_the_gpu`; the
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

/// The additive loop (docs/shadow-volumes.md, "Several lights"), emulated against Ogre's
/// per-light stencil loop, at 1x: every built-in scene (the `lights` scene's three lights
/// among them), z-fail and the scene's own choice, all three normalisations at k = 1, pixel for
/// pixel, and the subpass mask also on a device without fragment atomics. k = 4 (blend
/// arithmetic only, as `increment_and_darkness_change_only_the_blend_arithmetic` says) runs on
/// `overlap` and `lights`, the scenes with the deepest counts and the most lights.
/// tests/inside/plan.rs runs every scene's additive loop at 4x, and tests/inside/msaa_samples.rs
/// k = 4 at 4x.
#[test]
fn additive_emulated_equals_reference_on_every_scene() {
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
                for &normalize in Normalize::ALL {
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
                                rec.draw_fullscreen();
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

/// Names of the passes a frame drew.
fn pass_names(frame: &Frame) -> Vec<&str> {
    frame.output.counters.passes.iter().map(|p| p.name.as_str()).collect()
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

/// Every built-in scene, z-fail and the scene's own choice, in the seed's frame (k = 1,
/// D = 102): each emulated normalisation equals the reference pixel for pixel (the subpass apply
/// counting no saturation), with volumes clipped to the receivers' bounds, the default. Clipped
/// volumes, each drawn inside its own scissor and the apply inside their union, draw the
/// unclipped image and rasterise fewer volume fragments. "The same image" up to rounding: a
/// clipped wall is another triangle in the same plane, so its depth is rounded differently where
/// it grazes a surface (a caster's own terminator, a face lying along the light), and there a
/// pixel may flip. Unclipped, the emulated seed path still equals its reference exactly: the
/// other normalisations read the same counts (`normalisation_table_is_read_back_from_the_gpu`).
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
        // Clipping flips a grazing pixel now and then (`clipped_volumes_draw_the_unclipped_image_with_fewer_fragments`):
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

/// The box scene with a roof over its box and a second, smaller box under the roof: from the
/// sun both boxes lie wholly in the roof's shadow, so they cast nothing new (the nested parts of
/// an assembly, in miniature).
fn nested_scene() -> Scene {
    let mut scene = builtin_scene("box").expect("scene");
    let cube = scene.add_mesh("roof", nostencil::mesh::shapes::cube(1.0));
    let roof = Mat4::from_scale_rotation_translation(
        Vec3::new(3.4, 0.2, 3.4),
        glam::Quat::IDENTITY,
        Vec3::new(-0.8, 3.6, 0.2),
    );
    scene.add_object("roof", cube, roof, Vec3::new(0.7, 0.7, 0.72), true);
    let small = scene.add_mesh("small box", nostencil::mesh::shapes::cube(1.0));
    let place = Mat4::from_scale_rotation_translation(Vec3::splat(0.5), glam::Quat::IDENTITY, Vec3::new(0.6, 0.6, 0.3));
    scene.add_object("small box", small, place, Vec3::new(0.85, 0.4, 0.3), true);
    scene
}

/// Casters wholly in the shadow of other casters cast nothing new (CC Shadow Volumes' culling,
/// docs/shadow-volumes.md "Casters culled"): with culling on and off the reference draws the same
/// image and the emulated seed path equals it, on every built-in scene and on a nested one, in
/// both modes and both counting methods; culling never raises the volumes' fragments, and on the
/// nested scene it culls both boxes and saves fragments. Where culling culls a caster, every
/// normalisation is checked too, at 1 and 4 samples. Where it culls none, the culled frame draws
/// the unculled volumes, whose every normalisation at 1x is proven by
/// `emulated_equals_reference_on_every_scene_clipped_or_not` and `additive_*`, and at 4x by
/// tests/inside/plan.rs. (Every case once ran all five frames at both sample counts: 520 frames,
/// 41 s.)
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
                    let normalisations = if culls { Normalize::ALL } else { &[Normalize::Seed][..] };
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

/// The volume passes' vertex invocations, clipping primitives and fragment invocations.
fn volume_work(frame: &Frame) -> [u64; 3] {
    let volumes = frame.output.counters.passes.iter().filter(|p| p.name.contains("volumes"));
    volumes.fold([0; 3], |[v, p, f], pass| {
        let count = |c: Option<u64>| c.expect("lavapipe has pipeline statistics");
        [v + count(pass.vertex_invocations), p + count(pass.clipping_primitives), f + count(pass.fragment_invocations)]
    })
}

/// Each near cap of an open caster drawn only by the counting pipeline that can see it past its
/// own face (docs/shadow-volumes.md, "Near caps under their faces"): on every built-in scene of
/// open casters, in both modes and at 1 and 4 samples, the frame is the one with every near cap
/// drawn by both pipelines (`--whole-near-caps`) and the reference's, in every normalisation,
/// for less vertex and primitive work and no more fragments; z-fail, whose near caps count at
/// their faces' own depth, draws them all.
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
                for &normalize in Normalize::ALL {
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
