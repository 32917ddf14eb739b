//! Passes as data, checked: for every technique and every variant of its plan, the passes the
//! recorder actually ran in a frame, with the labels of the pipelines each bound, are exactly
//! the plan that `nostencil passes` prints.

mod common;

use nostencil::scene::builtin_scene;
use nostencil::technique::{RenderOptions, TECHNIQUES};

#[test]
fn every_frame_runs_exactly_its_printed_plan() {
    let gpu = common::gpu();
    let scene = builtin_scene("default").expect("default scene");
    let mut checked = 0;
    for technique in TECHNIQUES {
        let base = RenderOptions { width: 64, height: 48, technique: *technique, ..Default::default() };
        for variant in technique.plan_variants(&base) {
            let printed = technique.plan(&variant.options).expect("plan");
            let mut renderer = technique.build(&gpu, &scene, &variant.options).expect("renderer");
            // The first frame and the steady state (a cached shadow map skips passes).
            for frame_index in 0..renderer.frames_to_steady_state() {
                let frame = renderer.frame_with(&scene).expect("frame");
                let expected = printed.expected_trace(|when| frame.held(when));
                assert!(!expected.is_empty(), "{}: empty plan", variant.label);
                assert_eq!(
                    frame.output.trace, expected,
                    "{} (frame {frame_index}): the passes that ran differ from the printed plan",
                    variant.label
                );
                checked += 1;
            }
            assert_eq!(renderer.plan().passes.len(), printed.passes.len(), "{}", variant.label);
        }
    }
    assert!(checked >= TECHNIQUES.len() * 2, "only {checked} frames checked");
    common::assert_no_validation_messages(&gpu);
}
