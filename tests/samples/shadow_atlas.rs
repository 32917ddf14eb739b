//! examples/shadow_atlas.rs (seed 004's shadow textures, baked into an atlas page) proven equal
//! to its `--stencil` frame and to the engine's frame of the same scene and settings, on the
//! validating GPU.

use nostencil::{AtlasBake, LightMode, RenderOptions, StencilMode};

use super::{darkened, differing, engine};
use crate::common;

#[allow(dead_code)]
#[path = "../../examples/shadow_atlas.rs"]
mod sample;

#[test]
fn shadow_atlas_equals_its_stencil_and_the_engine() {
    let gpu = common::gpu();
    let alpha = sample::render(&gpu, sample::SCENE, false).expect("the alpha frame");
    let stencil = sample::render(&gpu, sample::SCENE, true).expect("the stencil frame");
    let size = |technique: &str| RenderOptions {
        width: sample::WIDTH,
        height: sample::HEIGHT,
        samples: 1,
        technique: common::technique(technique),
        stencil: StencilMode::Emulated,
        ..RenderOptions::default()
    };
    let mut options = size("shadow-texture-atlas");
    options.shadow_atlas.bake = AtlasBake::Rasterised;
    options.shadow_atlas.light = LightMode::Fixed;
    options.shadow_atlas.map_size = sample::MAP_SIZE;
    options.shadow_atlas.texture_size = sample::TEXTURE_SIZE;
    let emulated = engine(&gpu, sample::SCENE, &options);
    options.stencil = StencilMode::Reference;
    let reference = engine(&gpu, sample::SCENE, &options);
    let lit = engine(&gpu, sample::SCENE, &size("lit"));
    assert_eq!(differing(&alpha, &stencil), 0, "alpha against --stencil");
    assert_eq!(differing(&alpha, &emulated), 0, "the sample against the engine");
    assert_eq!(differing(&stencil, &reference), 0, "--stencil against the engine's reference path");
    let shadowed = darkened(&alpha, &lit);
    assert!(shadowed > 200, "{shadowed} pixels in shadow: the box must cast one (252 on lavapipe)");
    common::assert_no_validation_messages(&gpu);
}
