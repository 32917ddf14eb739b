//! The one-file samples of `examples/` (docs/porting.md), each proven as the issue that asked
//! for them says: its alpha frame equals its own `--stencil` frame, and equals the engine's frame
//! of the same scene and settings, pixel for pixel (RGB: alpha is the emulated stencil's scratch
//! space). Each sample is compiled into this test as a module and called with a validating GPU.

use crate::common;

use image::RgbaImage;
use nostencil::{render_scene, RenderOptions, StencilMode};

// One file per other sample (tests/samples/), each with its own test.
mod outline;
mod planar_shadows;
mod shadow_atlas;
mod silhouette;

// Each sample's `main` is its program's; the tests call its `render`.
#[allow(dead_code)]
#[path = "../examples/shadow_volumes.rs"]
mod shadow_volumes;

/// Pixels whose RGB differ between `a` and `b` (of the same size).
pub(crate) fn differing(a: &RgbaImage, b: &RgbaImage) -> usize {
    assert_eq!(a.dimensions(), b.dimensions());
    a.pixels().zip(b.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count()
}

/// The engine's frame of built-in scene `scene` with `options` (its size and technique set by
/// the caller), on `gpu`.
pub(crate) fn engine(gpu: &std::sync::Arc<nostencil::Gpu>, scene: &str, options: &RenderOptions) -> RgbaImage {
    let scene = nostencil::builtin_scene(scene).expect("a built-in scene");
    render_scene(gpu, &scene, options).expect("the engine's frame").output.image
}

/// Pixels `frame` darkens against `lit` (every channel no brighter, one darker): its shadow.
pub(crate) fn darkened(frame: &RgbaImage, lit: &RgbaImage) -> usize {
    frame
        .pixels()
        .zip(lit.pixels())
        .filter(|(f, l)| (0..3).all(|c| f.0[c] <= l.0[c]) && (0..3).any(|c| f.0[c] < l.0[c]))
        .count()
}

#[test]
fn shadow_volumes_equals_its_stencil_and_the_engine_in_z_pass_and_z_fail() {
    let gpu = common::gpu();
    let size = |technique: &str| RenderOptions {
        width: shadow_volumes::WIDTH,
        height: shadow_volumes::HEIGHT,
        samples: 1,
        technique: common::technique(technique),
        ..RenderOptions::default()
    };
    // The box: z-pass; inside (the camera under a floating slab, in its shadow): z-fail.
    for (scene, zfail) in [("box", false), ("inside", true)] {
        let base = nostencil::sample::SampleBase::new(&gpu, scene, 8, 8, false).expect("a base");
        assert_eq!(base.camera_in_a_volume(), zfail, "{scene}: the method the sample picks");
        drop(base);
        let alpha = shadow_volumes::render(&gpu, scene, false).expect("the alpha frame");
        let stencil = shadow_volumes::render(&gpu, scene, true).expect("the stencil frame");
        let mut options = size("shadow-volume");
        options.stencil = StencilMode::Emulated;
        options.shadow_mode = nostencil::ShadowMode::Modulate;
        options.shadow_volume.normalize = nostencil::Normalize::Seed;
        options.shadow_volume.clip_volumes = false;
        let engine = engine(&gpu, scene, &options);
        let lit = engine_lit(&gpu, scene, &size("lit"));
        assert_eq!(differing(&alpha, &stencil), 0, "{scene}: alpha against --stencil");
        assert_eq!(differing(&alpha, &engine), 0, "{scene}: the sample against the engine");
        let shadowed = darkened(&alpha, &lit);
        assert!(shadowed > 100, "{scene}: {shadowed} pixels in shadow: the frame must show one");
    }
    common::assert_no_validation_messages(&gpu);
}

fn engine_lit(gpu: &std::sync::Arc<nostencil::Gpu>, scene: &str, options: &RenderOptions) -> RgbaImage {
    engine(gpu, scene, options)
}

/// Each sample stays one readable file of at most 500 lines, takes no option beyond its two, and
/// docs/porting.md's table gives its true length.
#[test]
fn each_sample_is_one_file_of_at_most_500_lines_counted_right_in_the_porting_guide() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let guide = std::fs::read_to_string(root.join("docs/porting.md")).expect("docs/porting.md");
    for name in ["shadow_volumes", "planar_shadows", "outline", "silhouette", "shadow_atlas"] {
        let text = std::fs::read_to_string(root.join(format!("examples/{name}.rs"))).expect("the sample");
        let lines = text.lines().count();
        assert!(lines <= 500, "examples/{name}.rs has {lines} lines");
        let row = format!("[`examples/{name}.rs`](../examples/{name}.rs) | {lines} |");
        assert!(guide.contains(&row), "docs/porting.md does not give examples/{name}.rs's {lines} lines");
        assert!(text.contains(&format!("nostencil::sample::run(\"{name}\"")), "{name}'s main is not the base's");
    }
}
