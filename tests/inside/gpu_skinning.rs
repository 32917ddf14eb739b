//! Skinning in the vertex stage (`--skinning gpu`, the default): every technique draws a
//! GPU-skinned frame that matches the CPU-skinned frame (`--skinning cpu`), the oracle,
//! within 2 levels per channel apart from at most 0.5% of pixels (where rounding moves an
//! edge), with emulated still equal to reference to the byte; scenes re-posed after they were
//! built (the palettes move, the meshes do not) are drawn in their new pose. Every technique
//! says where it skinned.

use crate::common::{self, technique};

use image::RgbaImage;
use nostencil::render::Skinning;
use nostencil::{builtin_scene_at, scene_from_gltf, RenderOptions, Scene, StencilMode};

const SIZE: (u32, u32) = (128, 96);

/// The largest difference of any channel, and the share of pixels that differ by more than 2.
fn difference(a: &RgbaImage, b: &RgbaImage) -> (u8, f64) {
    assert_eq!(a.dimensions(), b.dimensions());
    let mut over = 0usize;
    let mut largest = 0u8;
    for (p, q) in a.pixels().zip(b.pixels()) {
        let d = p.0.iter().zip(q.0).map(|(x, y)| x.abs_diff(y)).max().unwrap_or(0);
        largest = largest.max(d);
        over += usize::from(d > 2);
    }
    (largest, over as f64 / (a.width() * a.height()) as f64)
}

/// Pixels whose colour differs.
fn rgb_differences(a: &RgbaImage, b: &RgbaImage) -> usize {
    a.pixels().zip(b.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count()
}

/// Each scene twice: built at its time (what the CPU-skinned oracle draws: a CPU renderer
/// takes the meshes as built to be in the scene's pose), and, for the built-in ones, built at
/// 0 then re-posed to that time (the palettes moved, the meshes did not), which the GPU skins.
fn scenes() -> Vec<(String, Scene, Scene)> {
    let mut scenes = Vec::new();
    for (name, time) in [("default", 0.6), ("character", 0.35)] {
        let mut reposed = builtin_scene_at(name, 0.0).expect("scene");
        reposed.pose_at(time).expect("pose");
        scenes.push((format!("{name} at {time}"), builtin_scene_at(name, time).expect("scene"), reposed));
    }
    // A glTF scene's camera frames the pose it is built in: these are built in theirs.
    for file in ["RiggedSimple.glb", "SimpleSkin.gltf"] {
        let scene = scene_from_gltf(&common::test_asset(file), 0.7).expect("glTF");
        scenes.push((format!("{file} at 0.7"), scene.clone(), scene));
    }
    scenes
}

fn frame(gpu: &std::sync::Arc<nostencil::Gpu>, scene: &Scene, options: &RenderOptions) -> (RgbaImage, Skinning) {
    let mut renderer = options.technique.build(gpu, scene, options).expect("renderer");
    let skinning = renderer.skinning();
    (renderer.frame_with(scene).expect("frame").output.image, skinning)
}

/// How a variant changes the default options.
type Vary = fn(&mut RenderOptions);

#[test]
fn gpu_skinned_frames_match_cpu_skinned_frames_and_emulated_equals_reference() {
    let gpu = common::gpu();
    let variants: [(&str, Vary); 18] = [
        ("lit", |_| {}),
        ("x-ray", |_| {}),
        ("toon", |_| {}),
        ("silhouette", |_| {}),
        ("silhouette", |o| o.cartoon.silhouette = nostencil::SilhouetteMethod::Hull),
        ("outline", |_| {}),
        ("outline", |o| o.cartoon.outline_blur = 4),
        ("shadow-map", |_| {}),
        ("projective-texture", |_| {}),
        ("shadow-texture-atlas", |_| {}),
        ("planar", |_| {}),
        ("blob", |_| {}),
        ("shadow-texture", |_| {}),
        ("shadow-volume", |_| {}),
        ("shadow-volume", |o| o.shadow_volume.method = nostencil::VolumeMethod::ZFail),
        ("shadow-volume", |o| o.shadow_mode = nostencil::ShadowMode::Modulate),
        ("shadow-volume", |o| o.shadow_volume.extrusion = nostencil::VolumeExtrusion::Shader),
        ("shadow-volume", |o| o.samples = 4),
    ];
    for (scene_name, built, scene) in scenes() {
        for (index, (name, vary)) in variants.iter().enumerate() {
            let mut options =
                RenderOptions { width: SIZE.0, height: SIZE.1, technique: technique(name), ..Default::default() };
            vary(&mut options);
            let what = format!("{scene_name}: {name} (variant {index})");
            // The atlas lays a skinned mesh out in the pose it was built in: drawn re-posed, its
            // texels sample the map elsewhere whoever skins it. It draws the scene as built.
            let scene = if *name == "shadow-texture-atlas" { &built } else { &scene };
            let (on_gpu, skinning) = frame(&gpu, scene, &options);
            assert_eq!(skinning, Skinning::Gpu, "{what}");
            let cpu = RenderOptions { skinning: Skinning::Cpu, ..options.clone() };
            let (on_cpu, skinning) = frame(&gpu, &built, &cpu);
            assert_eq!(skinning, Skinning::Cpu, "{what}");
            let (largest, share) = difference(&on_gpu, &on_cpu);
            // The issue allows 0.5% at edges; lavapipe shows none past 2 levels, and a volume
            // whose far points are left in the bind pose moves only 0.5%.
            assert!(
                share <= 0.001,
                "{what}: {:.2}% of pixels differ by more than 2 (largest {largest})",
                share * 100.0
            );
            if ["x-ray", "shadow-volume", "silhouette", "outline", "planar", "blob", "shadow-texture"].contains(name) {
                let reference = RenderOptions { stencil: StencilMode::Reference, ..options.clone() };
                // Alpha holds what the emulated counter leaves: the image is its colour.
                let differ = rgb_differences(&frame(&gpu, scene, &reference).0, &on_gpu);
                assert_eq!(differ, 0, "{what}: emulated differs from reference");
            }
        }
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn a_frame_skinned_on_the_gpu_follows_the_pose_not_the_mesh_it_was_built_with() {
    // The walk built at 0, re-posed to 0.6: the meshes keep the first pose, the palettes hold
    // the second. Drawn from the palettes, the frame is the one built at 0.6, and not the one
    // built at 0 (so the comparison above can fail).
    let gpu = common::gpu();
    let options = RenderOptions { width: SIZE.0, height: SIZE.1, technique: technique("lit"), ..Default::default() };
    let mut walk = builtin_scene_at("default", 0.0).expect("scene");
    let (before, _) = frame(&gpu, &walk, &options);
    walk.pose_at(0.6).expect("pose");
    let (after, skinning) = frame(&gpu, &walk, &options);
    assert_eq!(skinning, Skinning::Gpu);
    let built_there = builtin_scene_at("default", 0.6).expect("scene");
    let cpu = RenderOptions { skinning: Skinning::Cpu, ..options.clone() };
    let (oracle, _) = frame(&gpu, &built_there, &cpu);
    assert!(difference(&after, &oracle).1 <= 0.005);
    assert!(difference(&after, &before).1 > 0.01, "the re-posed frame must show the new pose");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn each_technique_says_where_it_skins() {
    let gpu = common::gpu();
    let scene = builtin_scene_at("default", 0.0).expect("scene");
    for &technique in nostencil::TECHNIQUES {
        for &skinning in Skinning::ALL {
            let options = RenderOptions { width: 32, height: 24, technique, skinning, ..Default::default() };
            let renderer = options.technique.build(&gpu, &scene, &options).expect("renderer");
            assert_eq!(renderer.skinning(), skinning, "{}", technique.name());
        }
    }
    common::assert_no_validation_messages(&gpu);
}
