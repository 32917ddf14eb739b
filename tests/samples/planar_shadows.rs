//! `examples/planar_shadows.rs`: its alpha frame equals its `--stencil` frame and the engine's
//! (`--technique planar --shadow-mode modulate`, one sample), and shows the shadows, each
//! receiver pixel darkened once however many flattened faces cover it.

use nostencil::{RenderOptions, ShadowMode, StencilMode};

use super::{darkened, differing, engine};
use crate::common;

#[allow(dead_code)]
#[path = "../../examples/planar_shadows.rs"]
mod sample;

#[test]
fn planar_shadows_equals_its_stencil_and_the_engine_darkening_once() {
    let gpu = common::gpu();
    let options = |technique: &str| RenderOptions {
        width: sample::WIDTH,
        height: sample::HEIGHT,
        samples: 1,
        technique: common::technique(technique),
        ..RenderOptions::default()
    };
    let alpha = sample::render(&gpu, sample::SCENE, false).expect("the alpha frame");
    let stencil = sample::render(&gpu, sample::SCENE, true).expect("the stencil frame");
    let mut planar = options("planar");
    planar.stencil = StencilMode::Emulated;
    planar.shadow_mode = ShadowMode::Modulate;
    let by_engine = engine(&gpu, sample::SCENE, &planar);
    let lit = engine(&gpu, sample::SCENE, &options("lit"));
    assert_eq!(differing(&alpha, &stencil), 0, "alpha against --stencil");
    assert_eq!(differing(&alpha, &by_engine), 0, "the sample against the engine");
    let shadowed = darkened(&alpha, &lit);
    assert!(shadowed > 500, "{shadowed} pixels in shadow: the frame must show the overlapping shadows");
    // Darkened once: every shadowed pixel is the lit one times F/255 (102), in linear light,
    // within a rounding step; twice would be times (F/255)^2.
    let linear = |byte: u8| {
        let c = f32::from(byte) / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let twice = alpha
        .pixels()
        .zip(lit.pixels())
        .filter(|(a, l)| a.0[..3] != l.0[..3])
        .filter(|(a, l)| (0..3).any(|c| (linear(a.0[c]) - linear(l.0[c]) * 0.4).abs() > 0.01))
        .count();
    assert_eq!(twice, 0, "pixels not darkened exactly once");
    common::assert_no_validation_messages(&gpu);
}
