//! Passes as data, checked: for every technique and every variant of its plan, the passes the
//! recorder actually ran in a frame, with the labels of the pipelines each bound, are exactly
//! the plan that `nostencil passes` prints.

use crate::common;

use nostencil::builtin_scene;
use nostencil::render::plan::When;
use nostencil::technique::planar::receiver::{LIGHT_ABOVE_PLANE, LIGHT_REACHES_PLANE};
use nostencil::technique::shadow_atlas::passes::{LIGHT_OR_CASTERS_MOVED, RASTERISED_TILES_STALE};
use nostencil::StencilMode;
use nostencil::{render_scene, LightMode, RenderOptions, TECHNIQUES};

/// Which conditional passes must run in frame `index` of the default scene, decided here and
/// not by the renderer: the first frame bakes everything; a moving light re-bakes every frame,
/// a fixed one never again (and the default scene has no geometry image: every re-baked tile is
/// rasterised); the default scene's light (its one light, the sun) is above the ground plane.
fn must_hold(when: When, index: u32, options: &RenderOptions) -> bool {
    let first_or_moving = index == 0 || options.shadow_atlas.light == LightMode::Moving;
    match when {
        When::Always => true,
        When::If(c) if c == LIGHT_ABOVE_PLANE || c == LIGHT_REACHES_PLANE.for_light(0) => true,
        When::If(c) if c == LIGHT_OR_CASTERS_MOVED || c == RASTERISED_TILES_STALE => first_or_moving,
        When::If(_) => false,
    }
}

#[test]
fn every_frame_runs_exactly_its_printed_plan() {
    let gpu = common::gpu();
    let scene = builtin_scene("default").expect("default scene");
    for technique in TECHNIQUES {
        let base = RenderOptions { width: 64, height: 48, technique: *technique, ..Default::default() };
        let variants = technique.plan_variants(&base);
        assert!(!variants.is_empty(), "{}: no plan to check", technique.name());
        for variant in variants {
            let printed = technique.plan(&variant.options, &technique.planned_lights(&scene)).expect("plan");
            assert!(!printed.passes.is_empty(), "{}: empty plan", variant.label);
            let mut renderer = technique.build(&gpu, &scene, &variant.options).expect("renderer");
            // The first frame and the next (where a fixed light's cached passes are skipped).
            for index in 0..2 {
                let frame = renderer.frame_with(&scene).expect("frame");
                let expected = printed.expected_trace(|when| must_hold(when, index, &variant.options));
                assert_eq!(
                    frame.output.trace, expected,
                    "{} (frame {index}): the passes that ran differ from the printed plan",
                    variant.label
                );
                for when in [
                    LIGHT_OR_CASTERS_MOVED,
                    RASTERISED_TILES_STALE,
                    LIGHT_ABOVE_PLANE,
                    LIGHT_REACHES_PLANE.for_light(0),
                ]
                .map(When::If)
                {
                    let planned = printed.passes.iter().any(|p| p.when == when);
                    let expected = must_hold(when, index, &variant.options);
                    assert!(!planned || frame.held(when) == expected, "{} (frame {index}): {when:?}", variant.label);
                }
            }
        }
    }
    common::assert_no_validation_messages(&gpu);
}

/// Every technique draws the same image without a stencil as with one, pixel for pixel (RGB:
/// alpha is each path's working state), on scenes with shadows, outlines and ink to get wrong,
/// open and non-manifold casters included, and on seed 004's 131,072-face model.
#[test]
fn every_technique_without_a_stencil_equals_its_stencil_reference() {
    let gpu = common::gpu();
    // Per technique: the pixels it changes from the lit image, over the scenes.
    let mut changed_over_scenes = vec![0usize; TECHNIQUES.len()];
    for scene_name in ["default", "outline", "open-box", "touching", "atlas-one"] {
        let scene = builtin_scene(scene_name).expect("scene");
        let lit = RenderOptions { width: 96, height: 72, ..Default::default() };
        let lit_image = render_scene(&gpu, &scene, &lit).expect("lit").output.image;
        for (changed_sum, technique) in changed_over_scenes.iter_mut().zip(TECHNIQUES) {
            let emulated = RenderOptions { technique: *technique, ..lit.clone() };
            let reference = RenderOptions { stencil: StencilMode::Reference, ..emulated.clone() };
            let a = render_scene(&gpu, &scene, &emulated).expect("emulated").output.image;
            let b = render_scene(&gpu, &scene, &reference).expect("reference").output.image;
            assert_eq!(a.dimensions(), b.dimensions());
            let differing = a.pixels().zip(b.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count();
            assert_eq!(differing, 0, "{} on {scene_name}: {differing} pixels differ", technique.name());
            *changed_sum += a.pixels().zip(lit_image.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count();
        }
    }
    // Not vacuous: every technique but the lit base changes the lit image (x-ray only where
    // something hides a caster: nowhere in open-box).
    for (changed, technique) in changed_over_scenes.iter().zip(TECHNIQUES) {
        assert!(technique.name() == "lit" || *changed > 50, "{}: only {changed} pixels", technique.name());
    }
    common::assert_no_validation_messages(&gpu);
}

/// At 4x MSAA every technique, in every variant of its plan (each shadow-volume normalisation
/// and counting method, each silhouette method, ...), draws without a stencil exactly the
/// resolved image of its real-stencil reference: blending and the stencil test are per sample,
/// and the subpass apply writes per sample (docs/design/msaa.md). What 4x changes is per sample
/// and the same on any geometry, so this runs on the scenes that reach each kind of frame:
/// `default` (every technique's general case), `inside` (z-fail), `open-quad` (a two-sided
/// caster and its near caps), `lights` (three lights in the additive loop), `duck` (ink on
/// curved surfaces), and seed 004's `atlas-one` for the shadow-texture family it was made for.
/// Every built-in scene meets every technique at 1x in
/// `every_technique_without_a_stencil_equals_its_stencil_reference`, and the counter's value in
/// every sample is read back in `msaa_samples.rs`.
#[test]
fn multisampled_frames_without_a_stencil_equal_their_stencil_reference() {
    const SCENES: [&str; 6] = ["default", "inside", "open-quad", "lights", "duck", "atlas-one"];
    let gpu = common::gpu();
    let (mut compared, mut edge_pixels) = (0, 0);
    for scene_name in SCENES {
        let scene = builtin_scene(scene_name).expect("scene");
        let base = RenderOptions { width: 64, height: 48, samples: 4, ..Default::default() };
        let one_sample = render_scene(&gpu, &scene, &RenderOptions { samples: 1, ..base.clone() }).expect("1x");
        let lit = render_scene(&gpu, &scene, &base).expect("lit 4x").output.image;
        // Not vacuous: 4x resolves object borders to colours the 1x frame does not have there.
        edge_pixels += lit.pixels().zip(one_sample.output.image.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count();
        let seed_004_family = ["lit", "shadow-map", "shadow-texture-atlas", "projective-texture"];
        for technique in TECHNIQUES {
            if scene_name == "atlas-one" && !seed_004_family.contains(&technique.name()) {
                continue;
            }
            let variants = technique.plan_variants(&RenderOptions { technique: *technique, ..base.clone() });
            for variant in variants.into_iter().filter(|v| v.options.stencil == StencilMode::Emulated) {
                let reference = RenderOptions { stencil: StencilMode::Reference, ..variant.options.clone() };
                let render = |options: &RenderOptions| render_scene(&gpu, &scene, options).map(|f| f.output.image);
                let (a, b) = match (render(&variant.options), render(&reference)) {
                    (Ok(a), Ok(b)) => (a, b),
                    // A scene the technique refuses (planar with no plane under the caster) is
                    // refused in both paths alike.
                    (Err(a), Err(b)) => {
                        assert_eq!(a.to_string(), b.to_string(), "{} on {scene_name}", variant.label);
                        continue;
                    }
                    (a, b) => {
                        panic!("{} on {scene_name}: one path failed: {:?} / {:?}", variant.label, a.err(), b.err())
                    }
                };
                let differing = a.pixels().zip(b.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count();
                assert_eq!(differing, 0, "{} on {scene_name} at 4x: {differing} pixels differ", variant.label);
                compared += 1;
            }
        }
    }
    println!("{compared} emulated/reference pairs equal at 4x; {edge_pixels} lit pixels resolved differently from 1x");
    assert!(edge_pixels > 100, "4x changed only {edge_pixels} pixels of the lit frames");
    common::assert_no_validation_messages(&gpu);
}
