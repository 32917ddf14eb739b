//! Shadow volumes cast by real glTF files (../shared/assets), skinned ones at their animated
//! pose: the emulated frame still equals the real-stencil reference pixel for pixel, and the
//! shadow is really there, on the ground under the casters and nowhere else.

mod common;

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use image::RgbaImage;
use nostencil::frame::StencilMode;
use nostencil::gpu::Gpu;
use nostencil::scene::{scene_from_gltf, Light, Scene};
use nostencil::technique::lit::Lit;
use nostencil::technique::shadow_volume::ShadowVolumes;
use nostencil::technique::shadow_volume::{Normalize, ShadowVolumeOptions};
use nostencil::technique::{render_scene, RenderOptions};

const SIZE: (u32, u32) = (128, 96);

fn lit(gpu: &Arc<Gpu>, scene: &Scene) -> RgbaImage {
    let options = RenderOptions { width: SIZE.0, height: SIZE.1, technique: &Lit, ..Default::default() };
    render_scene(gpu, scene, &options).expect("lit frame").output.image
}

fn shadowed(gpu: &Arc<Gpu>, scene: &Scene, stencil: StencilMode, options: &ShadowVolumeOptions) -> RgbaImage {
    let options = RenderOptions {
        width: SIZE.0,
        height: SIZE.1,
        stencil,
        technique: &ShadowVolumes,
        shadow_volume: *options,
        ..Default::default()
    };
    render_scene(gpu, scene, &options).expect("shadow-volume frame").output.image
}

/// Pixels whose RGB differ (alpha holds each path's working state and is not the image).
fn rgb_differences(a: &RgbaImage, b: &RgbaImage) -> usize {
    a.chunks_exact(4).zip(b.chunks_exact(4)).filter(|(p, q)| p[..3] != q[..3]).count()
}

/// Checks the shadow against the casters and returns how many ground pixels it darkened. A
/// shadow only darkens; on the visible ground (pixels the lit frame shows in the ground's lit
/// colour) every darkened pixel lies in the convex hull of the casters' vertices projected
/// along the light onto the ground, and the shadow covers a good share of that hull.
fn assert_ground_shadow(label: &str, scene: &Scene, shadowed: &RgbaImage, lit: &RgbaImage) -> usize {
    let Light::Directional { direction } = scene.light else {
        panic!("{label}: expected the default directional light")
    };
    let ground = scene.object("ground").expect("the scene has a ground");
    let height = ground.transform.transform_point3(scene.meshes[ground.mesh].data.positions[0]).y;
    let ground_colour = common::lit_ground(scene);
    let projected: Vec<Vec2> = scene
        .objects
        .iter()
        .filter(|o| o.casts_shadow)
        .flat_map(|o| scene.meshes[o.mesh].data.positions.iter().map(|p| o.transform.transform_point3(*p)))
        .map(|c| {
            let p = c + direction * ((c.y - height) / -direction.y);
            Vec2::new(p.x, p.z)
        })
        .collect();
    let hull = common::convex_hull(&projected);
    let under_casters = |x: u32, y: u32| {
        common::ground_point(&scene.camera, (x, y), SIZE, height)
            .is_some_and(|p| common::inside_hull(&hull, Vec2::new(p.x, p.z)))
    };
    let (mut ground_pixels, mut under, mut darkened, mut stray) = (0, 0, 0, Vec::new());
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let (s, l) = (shadowed.get_pixel(x, y).0, lit.get_pixel(x, y).0);
            assert!((0..3).all(|c| s[c] <= l[c]), "{label}: ({x}, {y}) is brighter than lit: {s:?} vs {l:?}");
            if !common::near(&l, &ground_colour, 1) {
                continue;
            }
            ground_pixels += 1;
            under += under_casters(x, y) as usize;
            if s[..3] != l[..3] {
                darkened += 1;
                // A pixel on the hull's border may go either way: its neighbours decide.
                let near_hull = (x.saturating_sub(1)..=x + 1)
                    .any(|nx| (y.saturating_sub(1)..=y + 1).any(|ny| under_casters(nx, ny)));
                if !near_hull {
                    stray.push((x, y));
                }
            }
        }
    }
    assert!(ground_pixels > (SIZE.0 * SIZE.1 / 10) as usize, "{label}: only {ground_pixels} ground pixels in view");
    assert!(stray.is_empty(), "{label}: ground darkened away from under the casters at {stray:?}");
    assert!(darkened > 50, "{label}: no shadow on the ground ({darkened} pixels)");
    assert!(darkened * 4 >= under, "{label}: only {darkened} of the {under} ground pixels under the casters are dark");
    darkened
}

#[test]
fn gltf_casters_match_the_reference_and_follow_the_skinned_pose() {
    let gpu = common::gpu();
    let mut rigged_images = Vec::new();
    for (file, time) in [("TorusKnot.glb", 0.0), ("Box.glb", 0.0), ("RiggedSimple.glb", 0.0), ("RiggedSimple.glb", 0.8)]
    {
        let path = common::shared_asset(file);
        let scene = scene_from_gltf(&path, time).expect("scene");
        assert!(scene.objects.iter().any(|o| o.casts_shadow), "{file}: no closed caster found (after welding)");
        let options = ShadowVolumeOptions::default();
        let reference = shadowed(&gpu, &scene, StencilMode::Reference, &options);
        let darkened = assert_ground_shadow(&format!("{file} at {time}s"), &scene, &reference, &lit(&gpu, &scene));
        println!("{file} at {time}s: {darkened} ground pixels in shadow");
        for &normalize in Normalize::ALL {
            let emulated = shadowed(&gpu, &scene, StencilMode::Emulated, &ShadowVolumeOptions { normalize, ..options });
            let differing = rgb_differences(&emulated, &reference);
            assert_eq!(differing, 0, "{file} at {time}s, {}", normalize.name());
        }
        if file == "RiggedSimple.glb" {
            rigged_images.push(reference);
        }
    }
    let moved = rigged_images[0].pixels().zip(rigged_images[1].pixels()).filter(|(a, b)| a != b).count();
    assert!(moved > 100, "the skinned pose (and its shadow) must move");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn open_gltf_meshes_receive_but_do_not_cast() {
    let gpu = common::gpu();
    let path = common::shared_asset("SimpleSkin.gltf");
    let scene = scene_from_gltf(&path, 0.5).expect("scene");
    assert!(scene.objects.iter().all(|o| !o.casts_shadow), "an open strip cannot cast a shadow volume");
    let options = ShadowVolumeOptions::default();

    // Nothing casts: the frame is the lit frame, the strip in it.
    let unshadowed = lit(&gpu, &scene);
    let frame = shadowed(&gpu, &scene, StencilMode::Emulated, &options);
    assert_eq!(rgb_differences(&frame, &unshadowed), 0, "no caster, yet pixels were darkened");
    let mut bare = scene.clone();
    bare.objects.retain(|o| o.name == "ground");
    let strip_pixels = rgb_differences(&unshadowed, &lit(&gpu, &bare));
    assert!(strip_pixels > 100, "the strip covers only {strip_pixels} pixels");

    // It receives: a closed box between the strip and the light darkens the strip.
    let Light::Directional { direction } = scene.light else { panic!("expected the default directional light") };
    let strip: Vec<Vec3> = scene
        .objects
        .iter()
        .filter(|o| o.name != "ground")
        .flat_map(|o| scene.meshes[o.mesh].data.positions.iter().map(|p| o.transform.transform_point3(*p)))
        .collect();
    let (lo, hi) = strip.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let (centre, size) = ((lo + hi) * 0.5, (hi - lo).length());
    let mut blocked = scene.clone();
    let cube = blocked.add_mesh("blocker", nostencil::mesh::shapes::cube(1.0));
    let place =
        Mat4::from_translation(centre - direction.normalize() * size) * Mat4::from_scale(Vec3::splat(size * 0.3));
    blocked.add_object("blocker", cube, place, Vec3::new(0.8, 0.3, 0.3), true);
    let reference = shadowed(&gpu, &blocked, StencilMode::Reference, &options);
    let emulated = shadowed(&gpu, &blocked, StencilMode::Emulated, &options);
    assert_eq!(rgb_differences(&emulated, &reference), 0, "emulated and reference differ with a caster");
    let lit_blocked = lit(&gpu, &blocked);
    let mut blocked_bare = blocked.clone();
    blocked_bare.objects.retain(|o| o.name == "ground" || o.name == "blocker");
    let without_strip = lit(&gpu, &blocked_bare);
    let darkened_strip = (0..SIZE.1)
        .flat_map(|y| (0..SIZE.0).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let shows_strip = lit_blocked.get_pixel(x, y).0[..3] != without_strip.get_pixel(x, y).0[..3];
            shows_strip && emulated.get_pixel(x, y).0[..3] != lit_blocked.get_pixel(x, y).0[..3]
        })
        .count();
    println!("SimpleSkin: {strip_pixels} strip pixels, {darkened_strip} of them darkened by the box");
    assert!(darkened_strip > 20, "the box's shadow does not fall on the strip ({darkened_strip} pixels)");
    common::assert_no_validation_messages(&gpu);
}
