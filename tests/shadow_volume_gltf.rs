//! Shadow volumes cast by real glTF files (../shared/assets), skinned ones at their animated
//! pose: the emulated frame still equals the real-stencil reference pixel for pixel.

mod common;

use nostencil::frame::StencilMode;
use nostencil::scene::scene_from_gltf;
use nostencil::technique::shadow_volume::{self, Normalize, ShadowVolumeOptions};

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
        let reference =
            shadow_volume::render(&gpu, &scene, 128, 96, StencilMode::Reference, &options).expect("reference");
        for normalize in Normalize::ALL {
            let emulated = shadow_volume::render(
                &gpu,
                &scene,
                128,
                96,
                StencilMode::Emulated,
                &ShadowVolumeOptions { normalize, ..options },
            )
            .expect("emulated");
            let differing = emulated
                .output
                .image
                .chunks_exact(4)
                .zip(reference.output.image.chunks_exact(4))
                .filter(|(a, b)| a[..3] != b[..3])
                .count();
            assert_eq!(differing, 0, "{file} at {time}s, {}", normalize.name());
        }
        if file == "RiggedSimple.glb" {
            rigged_images.push(reference.output.image);
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
    shadow_volume::render(&gpu, &scene, 64, 64, StencilMode::Emulated, &ShadowVolumeOptions::default())
        .expect("renders");
    common::assert_no_validation_messages(&gpu);
}
