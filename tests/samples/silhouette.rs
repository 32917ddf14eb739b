//! examples/silhouette.rs (ink found by silhouette edge detection, seed 002) proven equal to its `--stencil`
//! frame and to the engine's frame of the same scene and settings, on the validating GPU.

use nostencil::{RenderOptions, SilhouetteMethod, StencilMode};

use super::{differing, engine};
use crate::common;

#[allow(dead_code)]
#[path = "../../examples/silhouette.rs"]
mod sample;

#[test]
fn silhouette_equals_its_stencil_and_the_engine() {
    let gpu = common::gpu();
    let alpha = sample::render(&gpu, sample::SCENE, false).expect("the alpha frame");
    let stencil = sample::render(&gpu, sample::SCENE, true).expect("the stencil frame");
    let mut options = RenderOptions {
        width: sample::WIDTH,
        height: sample::HEIGHT,
        samples: 1,
        technique: common::technique("silhouette"),
        stencil: StencilMode::Emulated,
        ..RenderOptions::default()
    };
    options.cartoon.silhouette = SilhouetteMethod::Edges;
    options.cartoon.line_width = sample::LINE_WIDTH;
    let emulated = engine(&gpu, sample::SCENE, &options);
    options.stencil = StencilMode::Reference;
    let reference = engine(&gpu, sample::SCENE, &options);
    assert_eq!(differing(&alpha, &stencil), 0, "alpha against --stencil");
    assert_eq!(differing(&alpha, &emulated), 0, "the sample against the engine");
    assert_eq!(differing(&stencil, &reference), 0, "--stencil against the engine's reference path");
    // The ink shows: pixels in exactly the ink's colour (sRGB-encoded as the frame stores it).
    let ink = [56, 56, 69]; // sample::INK (linear 0.04, 0.04, 0.06) in sRGB
    let inked = alpha.pixels().filter(|p| p.0[..3] == ink).count();
    assert!(inked > 500, "{inked} ink pixels: the duck must be outlined (710 on lavapipe)");
    common::assert_no_validation_messages(&gpu);
}
