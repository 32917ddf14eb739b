//! Shadow volumes in alpha are proven against the real stencil, pixel for pixel, and against
//! hand-computed answers: the seed's normalisation table, a box's projected outline, a camera
//! inside a volume, and the background behind a volume.

mod common;

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use image::RgbaImage;
use nostencil::frame::render_pass::COLOUR_FORMAT;
use nostencil::frame::StencilMode;
use nostencil::gpu::Gpu;
use nostencil::mesh::MeshData;
use nostencil::render::Pipeline;
use nostencil::render::{FrameUniforms, Renderer};
use nostencil::scene::{builtin_scene, Scene, BUILTIN_SCENES};
use nostencil::technique::shadow_volume::{self, Normalize, ShadowVolumeOptions, VolumeMethod};
use nostencil::technique::{alpha_counter, render_scene, RenderOptions, Technique};

const SIZE: (u32, u32) = (128, 96);

/// A shadow-volume frame with the technique's statistics.
struct Frame {
    output: nostencil::FrameOutput,
    stats: nostencil::technique::ShadowVolumeStats,
}

fn render(gpu: &Arc<Gpu>, scene: &Scene, stencil: StencilMode, options: ShadowVolumeOptions) -> Frame {
    render_sized(gpu, scene, stencil, options, SIZE)
}

fn render_sized(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    options: ShadowVolumeOptions,
    size: (u32, u32),
) -> Frame {
    try_render(gpu, scene, stencil, options, size).expect("shadow-volume frame")
}

fn try_render(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    options: ShadowVolumeOptions,
    size: (u32, u32),
) -> nostencil::Result<Frame> {
    let options = RenderOptions {
        width: size.0,
        height: size.1,
        stencil,
        technique: technique("shadow-volume"),
        shadow_volume: options,
        ..Default::default()
    };
    let frame = render_scene(gpu, scene, &options)?;
    let stats = *frame.stats::<nostencil::technique::ShadowVolumeStats>().expect("shadow-volume statistics");
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

#[test]
fn emulated_equals_reference_for_every_scene_increment_and_normalisation() {
    let gpu = common::gpu();
    for (name, _) in BUILTIN_SCENES {
        let scene = builtin_scene(name).expect("scene");
        for method in [VolumeMethod::Auto, VolumeMethod::ZFail] {
            let base = ShadowVolumeOptions { method, ..Default::default() };
            let reference = render(&gpu, &scene, StencilMode::Reference, base);
            let unshadowed = lit(&gpu, &scene);
            let shadowed_pixels = shadow_mask(&reference.output.image, &unshadowed).iter().filter(|s| **s).count();
            assert!(shadowed_pixels > 50, "{name}: the reference shows no shadow ({shadowed_pixels} pixels)");
            for k in [1u8, 2, 4, 8] {
                for &normalize in Normalize::ALL {
                    let options = ShadowVolumeOptions { increment: k, normalize, ..base };
                    let emulated = render(&gpu, &scene, StencilMode::Emulated, options);
                    assert_eq!(emulated.stats.saturated_pixels, Some(0), "{name} k={k}");
                    let differing = rgb_differences(&emulated.output.image, &reference.output.image);
                    assert_eq!(differing, 0, "{name} {method:?} k={k} {}: {differing} pixels differ", normalize.name());
                }
            }
        }
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn normalisation_table_is_read_back_from_the_gpu() {
    // DESIGN.md: with k = 1 a count of 1 reads 0.9922, 0.9765, 0.9294, 0.7922, 0.4196, 0 after
    // N0 and each iteration (253, 249, 237, 202, 107, 0 in 8 bits).
    let gpu = common::gpu();
    let expected = [253u8, 249, 237, 202, 107, 0];
    assert_eq!(alpha_counter::seed_sequence(1), expected);
    let uniforms = FrameUniforms {
        view_proj: Mat4::IDENTITY,
        light: Vec4::ZERO,
        camera_position: Vec4::ZERO,
        shading: Vec4::ZERO,
    };
    for (steps, want) in expected.iter().enumerate() {
        let mut renderer = Renderer::new(&gpu, 8, 8, StencilMode::Emulated, false).expect("renderer");
        let n0 = Pipeline::new(&gpu, &shadow_volume::n0_desc(), renderer.targets.render_pass, &[]).expect("n0");
        let iteration = Pipeline::new(&gpu, &shadow_volume::iteration_desc(), renderer.targets.render_pass, &[])
            .expect("iteration");
        // The clear writes a count of 1 (alpha 1/255) everywhere.
        let output = renderer
            .render(&uniforms, [0.5, 0.5, 0.5, 1.0 / 255.0], |rec| {
                shadow_volume::record_seed_normalisation(rec, &n0, &iteration, steps)
            })
            .expect("frame");
        let alpha = output.image.get_pixel(3, 3).0[3];
        assert_eq!(alpha, *want, "after N0 and {steps} iteration(s)");
        // On the format the frame ships in: alpha is linear UNORM8 there, the colour sRGB.
        assert_eq!(renderer.targets.desc.colour.format, COLOUR_FORMAT);
        assert_eq!(COLOUR_FORMAT, ash::vk::Format::R8G8B8A8_SRGB);
        let grey = common::srgb_encode(0.5);
        assert!(output.image.chunks_exact(4).all(|p| p[3] == *want && p[..3] == [grey; 3]));
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn box_shadow_matches_its_projected_outline() {
    let gpu = common::gpu();
    let scene = builtin_scene("box").expect("scene");
    let nostencil::scene::Light::Directional { direction } = scene.light else { panic!("directional light") };
    let object = scene.object("box").expect("box");
    let corners: Vec<Vec3> =
        scene.meshes[object.mesh].data.positions.iter().map(|p| object.transform.transform_point3(*p)).collect();
    // Ground shadow of the box: the convex hull of its corners projected along the light.
    let projected: Vec<glam::Vec2> = corners
        .iter()
        .map(|c| {
            let p = *c + direction * (c.y / -direction.y);
            glam::Vec2::new(p.x, p.z)
        })
        .collect();
    let hull = common::convex_hull(&projected);

    const BIG: (u32, u32) = (256, 192);
    let (width, height) = BIG;
    let unshadowed = lit_sized(&gpu, &scene, BIG);
    for &normalize in Normalize::ALL {
        let frame = render_sized(
            &gpu,
            &scene,
            StencilMode::Emulated,
            ShadowVolumeOptions { normalize, ..Default::default() },
            BIG,
        );
        let mask = shadow_mask(&frame.output.image, &unshadowed);
        let box_pixels: Vec<bool> = {
            // Pixels where the lit frame shows the box itself are excluded: its own unlit faces
            // are in its volume but are not ground.
            let background = lit_without_box(&gpu, &scene, BIG);
            unshadowed.chunks_exact(4).zip(background.chunks_exact(4)).map(|(a, b)| a != b).collect()
        };
        let (mut both, mut either) = (0, 0);
        for y in 0..height {
            for x in 0..width {
                let i = (y * width + x) as usize;
                if box_pixels[i] {
                    continue;
                }
                let expected = common::ground_point(&scene.camera, (x, y), BIG, 0.0).is_some_and(|p| {
                    p.x.abs() < 7.0 && p.z.abs() < 7.0 && common::inside_hull(&hull, glam::Vec2::new(p.x, p.z))
                });
                both += (expected && mask[i]) as u32;
                either += (expected || mask[i]) as u32;
            }
        }
        let iou = both as f64 / either as f64;
        assert!(either > 200, "the shadow is too small to judge ({either} pixels)");
        assert!(iou > 0.99, "{}: intersection over union {iou:.4} ({both}/{either})", normalize.name());
    }
    common::assert_no_validation_messages(&gpu);
}

fn lit_without_box(gpu: &Arc<Gpu>, scene: &Scene, size: (u32, u32)) -> RgbaImage {
    let mut without = scene.clone();
    without.objects.retain(|o| o.name != "box");
    lit_sized(gpu, &without, size)
}

#[test]
fn camera_inside_a_volume_needs_zfail_and_auto_chooses_it() {
    let gpu = common::gpu();
    let scene = builtin_scene("inside").expect("scene");
    let reference = render(
        &gpu,
        &scene,
        StencilMode::Reference,
        ShadowVolumeOptions { method: VolumeMethod::ZFail, ..Default::default() },
    );
    let auto = render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions::default());
    assert!(auto.stats.zfail, "auto must choose z-fail with the camera inside the slab's volume");
    assert_eq!(rgb_differences(&auto.output.image, &reference.output.image), 0);
    let zpass = render(
        &gpu,
        &scene,
        StencilMode::Emulated,
        ShadowVolumeOptions { method: VolumeMethod::ZPass, ..Default::default() },
    );
    let wrong = rgb_differences(&zpass.output.image, &reference.output.image);
    assert!(
        wrong > (SIZE.0 * SIZE.1 / 10) as usize,
        "z-pass should visibly fail inside a volume ({wrong} pixels differ)"
    );

    // Same shadow as the analytic answer: the ground under the camera is in the slab's shadow,
    // ground far beyond the slab's shadow is lit.
    let unshadowed = lit(&gpu, &scene);
    let mask = shadow_mask(&auto.output.image, &unshadowed);
    let nostencil::scene::Light::Directional { direction } = scene.light else { panic!() };
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
            let frame =
                render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions { method, ..Default::default() });
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
    scene.light = nostencil::scene::Light::Directional { direction: Vec3::NEG_Y };
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

#[test]
fn saturation_is_reported_past_255_over_k() {
    let gpu = common::gpu();
    // 40 stacked layers: seen from the camera, ground pixels under the stack sit inside up to 40
    // volumes. k = 8 holds 31, k = 1 holds 255.
    let scene = stack_scene(40);
    let k1 = render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions::default());
    assert_eq!(k1.stats.capacity, 255);
    assert_eq!(k1.stats.saturated_pixels, Some(0));
    let k8 = render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions { increment: 8, ..Default::default() });
    assert_eq!(k8.stats.capacity, 31);
    assert!(k8.stats.saturated_pixels.unwrap_or(0) > 0, "k = 8 with 40 overlapping volumes must saturate");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn open_caster_is_refused_with_its_name() {
    let gpu = common::gpu();
    let mut scene = builtin_scene("box").expect("scene");
    let open = scene.add_mesh(
        "lonely quad",
        MeshData {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z],
            normals: vec![Vec3::Y; 4],
            uvs: vec![],
            indices: vec![0, 2, 1, 0, 3, 2],
        },
    );
    scene.add_object("quad", open, Mat4::from_translation(Vec3::Y), Vec3::ONE, true);
    let error = try_render(&gpu, &scene, StencilMode::Emulated, ShadowVolumeOptions::default(), (64, 64))
        .err()
        .expect("an open caster must be refused");
    let message = error.to_string();
    assert!(message.contains("lonely quad") && message.contains("closed"), "{message}");
    common::assert_no_validation_messages(&gpu);
}

/// A technique of the registry, by name.
fn technique(name: &str) -> &'static dyn Technique {
    nostencil::technique::by_name(name).expect("technique")
}
