//! Frames in flight: a renderer that submits frames without waiting for the one before draws
//! the same frames, to the byte, as one that waits for each, over the viewer's animation (the
//! walk re-posed, the casters turning): each frame's posed vertices, volumes, joint palettes,
//! blob quads, shadow-map light uniforms, atlas tile records and uniforms are written into its
//! own slot's copies. Its results come back as many frames late as it keeps
//! in flight.

use crate::common::{self, technique};

use nostencil::viewer::controls::Live;
use nostencil::{builtin_scene, RenderOptions, Scene, TechniqueFrame};

const SIZE: (u32, u32) = (96, 72);

/// The pass names, draws and counters of a frame, which must match as its image does.
fn counted(frame: &TechniqueFrame) -> Vec<(String, u32, u64, Option<u64>)> {
    let passes = &frame.output.counters.passes;
    passes.iter().map(|p| (p.name.clone(), p.draws, p.samples_passed, p.fragment_invocations)).collect()
}

#[test]
fn frames_in_flight_draw_every_frame_as_one_at_a_time_does_results_in_flight_frames_late() {
    let gpu = common::gpu();
    for scene_name in ["character", "default"] {
        let base: Scene = builtin_scene(scene_name).expect("scene");
        let names = [
            "lit",
            "shadow-volume",
            "planar",
            "blob",
            "shadow-texture",
            "x-ray",
            "silhouette",
            "silhouette hull",
            "toon",
            "outline",
            "outline blur",
            "shadow-map",
            "projective-texture",
            "shadow-texture-atlas",
        ];
        for name in names {
            let mut options = RenderOptions {
                width: SIZE.0,
                height: SIZE.1,
                technique: technique(name.split(' ').next().unwrap_or(name)),
                ..Default::default()
            };
            if name.ends_with("hull") {
                // The inverted hull: extruded copies re-posed per slot.
                options.cartoon.silhouette = nostencil::SilhouetteMethod::Hull;
            }
            if name.ends_with("blur") {
                // The blur's offscreen mask and passes, per slot.
                options.cartoon.outline_blur = 4;
            }
            // The frames one at a time, drawn once for both in-flight counts (each drew its own
            // until 2026-12: the same frames twice).
            let mut alone = options.technique.build(&gpu, &base, &options).expect("renderer");
            let (mut live, mut scene) = (Live::new(&base, false, 0.0), base.clone());
            let expected: Vec<TechniqueFrame> = (0..3 + 4)
                .map(|index| {
                    live.time = index as f32 * 0.1;
                    live.apply(&base, &mut scene).expect("pose");
                    alone.frame_with(&scene).expect("frame")
                })
                .collect();
            for in_flight in [2usize, 3] {
                let pipelined = RenderOptions { frames_in_flight: in_flight as u32, ..options.clone() };
                let mut renderer = pipelined.technique.build(&gpu, &base, &pipelined).expect("renderer");
                assert_eq!(renderer.frames_in_flight(), in_flight, "{scene_name} {name}");
                let (mut live, mut scene) = (Live::new(&base, false, 0.0), base.clone());
                for index in 0..in_flight + 4 {
                    live.time = index as f32 * 0.1;
                    live.apply(&base, &mut scene).expect("pose");
                    let late = renderer.frame_with(&scene).expect("frame");
                    let what = format!("{scene_name} {name}, {in_flight} in flight, frame {index}");
                    match index.checked_sub(in_flight) {
                        // Nothing has completed yet: no image, no passes.
                        None => {
                            assert_eq!(late.output.image.dimensions(), (0, 0), "{what}");
                            assert!(late.output.counters.passes.is_empty(), "{what}");
                        }
                        Some(earlier) => {
                            let reference = &expected[earlier];
                            assert!(late.output.image == reference.output.image, "{what}: frame {earlier} differs");
                            assert_eq!(counted(&late), counted(reference), "{what}: frame {earlier}'s counters");
                        }
                    }
                }
                // The frames drawn moved: the comparison saw the animation.
                let (first, last) = (&expected[in_flight].output.image, &expected[in_flight + 3].output.image);
                assert!(first != last, "{scene_name} {name}: nothing moved");
                renderer.wait_all().expect("finish");
            }
        }
    }
    // A heat map (its overdraw pipelines are cleared per frame) renders one frame at a time.
    let base = builtin_scene("default").expect("scene");
    let options = RenderOptions {
        width: SIZE.0,
        height: SIZE.1,
        frames_in_flight: 3,
        count_overdraw: true,
        technique: technique("shadow-volume"),
        ..Default::default()
    };
    let mut renderer = options.technique.build(&gpu, &base, &options).expect("renderer");
    assert_eq!(renderer.frames_in_flight(), 1);
    assert!(!renderer.frame_with(&base).expect("frame").output.counters.passes.is_empty());
    common::assert_no_validation_messages(&gpu);
}
