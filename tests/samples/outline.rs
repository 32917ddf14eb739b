//! `examples/outline.rs`: its alpha frame equals its `--stencil` frame and the engine's
//! (`--technique outline --select box`, one sample), and shows the outline.

use nostencil::{RenderOptions, StencilMode};

use super::{differing, engine};
use crate::common;

#[allow(dead_code)]
#[path = "../../examples/outline.rs"]
mod sample;

#[test]
fn outline_equals_its_stencil_and_the_engine() {
    let gpu = common::gpu();
    let alpha = sample::render(&gpu, sample::SCENE, false).expect("the alpha frame");
    let stencil = sample::render(&gpu, sample::SCENE, true).expect("the stencil frame");
    let mut options = RenderOptions {
        width: sample::WIDTH,
        height: sample::HEIGHT,
        samples: 1,
        technique: common::technique("outline"),
        stencil: StencilMode::Emulated,
        ..RenderOptions::default()
    };
    options.cartoon.select = sample::SELECTED.iter().map(|name| name.to_string()).collect();
    options.cartoon.outline_width = sample::OUTLINE_WIDTH;
    options.cartoon.outline_colour = sample::OUTLINE_COLOUR;
    let by_engine = engine(&gpu, sample::SCENE, &options);
    assert_eq!(differing(&alpha, &stencil), 0, "alpha against --stencil");
    assert_eq!(differing(&alpha, &by_engine), 0, "the sample against the engine");
    let outlined = alpha.pixels().filter(|p| p.0[..3] == sample::OUTLINE_COLOUR).count();
    assert!(outlined > 500, "{outlined} pixels in the outline colour: the frame must show the outline");
    common::assert_no_validation_messages(&gpu);
}
