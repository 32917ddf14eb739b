//! The selection outline's methods (seed 003): the document's uniformly scaled copy beside the
//! normal extrusion. Each is proven equal to its real-stencil reference pixel for pixel; the
//! scaled outline of a sphere is measured against the ring computed here from the projection;
//! and on a torus seen face-on the images show where the two methods differ.

use crate::common::{self, technique};

use std::sync::Arc;

use glam::{Mat4, Vec3};
use image::RgbaImage;
use nostencil::mesh::{shapes, MeshData};
use nostencil::Gpu;
use nostencil::StencilMode;
use nostencil::{builtin_scene, Camera, Light, Scene};
use nostencil::{render_scene, CartoonOptions, OutlineMethod, RenderOptions};

const SIZE: (u32, u32) = (160, 120);
/// The camera's distance from the shapes of the face-on scenes.
const DISTANCE: f32 = 5.0;

fn render(gpu: &Arc<Gpu>, scene: &Scene, stencil: StencilMode, cartoon: &CartoonOptions) -> RgbaImage {
    let options = RenderOptions {
        width: SIZE.0,
        height: SIZE.1,
        stencil,
        technique: technique("outline"),
        cartoon: cartoon.clone(),
        ..Default::default()
    };
    render_scene(gpu, scene, &options).expect("outline frame").output.image
}

fn rgb_differences(a: &RgbaImage, b: &RgbaImage) -> usize {
    a.chunks_exact(4).zip(b.chunks_exact(4)).filter(|(p, q)| p[..3] != q[..3]).count()
}

/// One selected shape at the origin, `transform` applied, seen from `DISTANCE` on +Z.
fn face_on_scene(mesh: MeshData, transform: Mat4) -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, DISTANCE), Vec3::ZERO);
    let light = Light::Directional { direction: Vec3::new(0.0, 0.0, -1.0) };
    let mut scene = Scene { background: Vec3::new(0.9, 0.9, 0.9), ..Scene::empty("face-on", camera, light) };
    let mesh = scene.add_mesh("shape", mesh);
    scene.add_object("shape", mesh, transform, Vec3::new(0.3, 0.5, 0.8), false);
    scene
}

/// Focal length in pixels: a point at height y, depth z in front of the eye lands
/// `FOCAL * y / z` pixels from the image centre.
fn focal_px(scene: &Scene) -> f32 {
    0.5 * SIZE.1 as f32 / (0.5 * scene.camera.fov_y_radians).tan()
}

/// Distance of pixel (x, y)'s centre from the image centre.
fn radius_px(x: u32, y: u32) -> f32 {
    let dx = x as f32 + 0.5 - 0.5 * SIZE.0 as f32;
    let dy = y as f32 + 0.5 - 0.5 * SIZE.1 as f32;
    (dx * dx + dy * dy).sqrt()
}

fn options(method: OutlineMethod, width: f32) -> CartoonOptions {
    CartoonOptions { outline_method: method, outline_width: width, ..CartoonOptions::default() }
}

#[test]
fn scaled_outline_emulated_equals_reference() {
    let gpu = common::gpu();
    let outline = builtin_scene("outline").expect("scene");
    let default = builtin_scene("default").expect("scene");
    let cases: [(&Scene, &[&str]); 4] = [
        (&outline, &["box"]),
        // The box and the sphere intersect: the scaled copies overlap each other's surfaces.
        (&outline, &["box", "sphere", "torus knot"]),
        (&outline, &["box", "sphere", "torus knot", "torus", "ground"]),
        (&default, &["torus", "torus knot"]),
    ];
    for (scene, names) in cases {
        let cartoon = CartoonOptions {
            select: names.iter().map(|s| s.to_string()).collect(),
            ..options(OutlineMethod::Scale, 4.0)
        };
        let reference = render(&gpu, scene, StencilMode::Reference, &cartoon);
        let emulated = render(&gpu, scene, StencilMode::Emulated, &cartoon);
        let label = format!("{} {names:?}", scene.name);
        let outlined = reference.chunks_exact(4).filter(|p| p[..3] == cartoon.outline_colour).count();
        assert!(outlined > 100, "{label}: the reference shows {outlined} outline pixels");
        let differing = rgb_differences(&emulated, &reference);
        assert_eq!(differing, 0, "{label}: {differing} pixels differ");
        // Not the extruded outline under another name.
        let extruded = render(
            &gpu,
            scene,
            StencilMode::Emulated,
            &CartoonOptions { outline_method: OutlineMethod::Extrude, ..cartoon.clone() },
        );
        assert!(rgb_differences(&emulated, &extruded) > 20, "{label}: scale draws what extrude draws");
    }
    common::assert_no_validation_messages(&gpu);
}

/// The scaled outline of a unit sphere `DISTANCE` from the eye is the ring between the
/// silhouettes of the sphere and of the sphere scaled by s = 1 + width * pixel * DISTANCE / 1
/// (pixel: the world size of one pixel at unit distance), each of radius
/// `FOCAL * tan(asin(a / DISTANCE))` for a sphere of radius a.
#[test]
fn scaled_outline_of_a_sphere_is_a_ring_of_the_expected_width() {
    let gpu = common::gpu();
    let scene = face_on_scene(shapes::uv_sphere(32, 64).expect("sphere"), Mat4::IDENTITY);
    let focal = focal_px(&scene);
    let silhouette = |a: f32| focal * (a / DISTANCE).asin().tan();
    for width in [3.0f32, 8.0] {
        let cartoon = options(OutlineMethod::Scale, width);
        let image = render(&gpu, &scene, StencilMode::Emulated, &cartoon);
        let pixel_at_unit_distance = 1.0 / focal;
        let scale = 1.0 + width * pixel_at_unit_distance * DISTANCE;
        let (inner, outer) = (silhouette(1.0), silhouette(scale));
        // The tessellation's chords lie within 0.1 px of the sphere here; pixel centres within
        // 1 px of either circle may go either way.
        let mut ring = 0;
        for (x, y, p) in image.enumerate_pixels() {
            let (r, is_outline) = (radius_px(x, y), p.0[..3] == cartoon.outline_colour);
            if r < inner - 1.0 {
                assert_eq!(p.0[3], 255, "width {width}: ({x}, {y}) at {r:.2} px is inside the sphere");
            } else if r > inner + 1.0 && r < outer - 1.0 {
                assert!(is_outline, "width {width}: ({x}, {y}) at {r:.2} px is in the ring [{inner:.2}, {outer:.2}]");
            } else if r > outer + 1.0 {
                assert!(!is_outline, "width {width}: ({x}, {y}) at {r:.2} px is outside the ring");
            }
            ring += is_outline as usize;
        }
        let area = std::f32::consts::PI * (outer * outer - inner * inner);
        assert!((ring as f32 - area).abs() < 0.06 * area, "width {width}: {ring} outline pixels, ring area {area:.1}");
        // The ring is about the width asked for (the perspective widens it slightly).
        assert!((outer - inner - width).abs() < 0.1 * width + 0.2, "width {width}: ring {inner:.2}..{outer:.2}");
    }
    common::assert_no_validation_messages(&gpu);
}

/// A torus seen along its axis is concave where the eye looks through its hole. Extruded along
/// the normals the copy's inner rim moves into the hole: an outline ring inside it. Scaled about
/// the centre the inner rim moves outwards under the torus itself (every point of the copy
/// projects farther from the centre than the point it was scaled from), so the hole has no
/// outline at all, while outside both methods draw a ring of about the width.
#[test]
fn on_a_torus_the_scaled_copy_leaves_the_hole_without_outline_and_the_extrusion_does_not() {
    let gpu = common::gpu();
    let (major, minor) = (1.0, 0.35);
    let torus = shapes::torus(major, minor, 64, 24).expect("torus");
    let scene = face_on_scene(torus, Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2));
    let focal = focal_px(&scene);
    // Pixels closer to the centre than the tube's centre line and not on the torus are the hole.
    let tube_centre = focal * major / DISTANCE;
    let outer_silhouette = focal * (major + minor) / DISTANCE;
    let width = 4.0;
    let count = |method: OutlineMethod| {
        let cartoon = options(method, width);
        let image = render(&gpu, &scene, StencilMode::Emulated, &cartoon);
        let reference = render(&gpu, &scene, StencilMode::Reference, &cartoon);
        assert_eq!(rgb_differences(&image, &reference), 0, "{method:?}: emulated differs from the reference");
        let outline = |x: u32, y: u32| image.get_pixel(x, y).0[..3] == cartoon.outline_colour;
        let (mut hole, mut outside) = (0usize, 0usize);
        for (x, y, _) in image.enumerate_pixels() {
            let r = radius_px(x, y);
            if outline(x, y) && r < tube_centre {
                hole += 1;
            } else if outline(x, y) && r > outer_silhouette - 1.0 {
                outside += 1;
            }
        }
        (hole, outside)
    };
    let (extruded_hole, extruded_outside) = count(OutlineMethod::Extrude);
    let (scaled_hole, scaled_outside) = count(OutlineMethod::Scale);
    // The hole's visible radius is about (major - minor) / DISTANCE * focal: a ring of the width
    // inside it covers at least half of 2 pi (r - width) width.
    let hole_radius = focal * (major - minor) / DISTANCE;
    let inner_ring = std::f32::consts::TAU * (hole_radius - width) * width;
    assert!(extruded_hole as f32 > 0.5 * inner_ring, "extrude: {extruded_hole} outline pixels in the hole");
    assert_eq!(scaled_hole, 0, "scale: outline pixels in the hole");
    // Outside, both draw a ring of about the width (the bounding sphere is the outer rim here).
    let outer_ring = std::f32::consts::TAU * outer_silhouette * width;
    for (method, outside) in [("extrude", extruded_outside), ("scale", scaled_outside)] {
        assert!(
            (outside as f32 - outer_ring).abs() < 0.25 * outer_ring,
            "{method}: {outside} px outside, ring {outer_ring:.0}"
        );
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn outline_colour_and_method_from_the_command_line() {
    let dir = common::scratch_dir("outline-cli");
    let out = dir.join("green.png");
    let path = out.to_str().expect("utf-8 path");
    let common_args = ["render", "--size", "96x64", "--scene", "outline", "--technique", "outline", "--out", path];
    for method in ["extrude", "scale"] {
        let mut args = common_args.to_vec();
        args.extend_from_slice(&["--outline-method", method, "--outline-colour", "#00FF00", "--outline-width", "3"]);
        args.extend_from_slice(&["--validation"]);
        common::run_ok(&args);
        let green = common::read_png(&out).pixels().filter(|p| p.0 == [0, 255, 0]).count();
        assert!(green > 50, "{method}: {green} pixels of #00FF00");
    }
    for (value, mentions) in [
        (&["--outline-colour", "FFA00"][..], "--outline-colour"),
        (&["--outline-colour", "#GG0000"][..], "--outline-colour"),
        (&["--outline-colour", "orange"][..], "--outline-colour"),
        (&["--outline-width", "0"][..], "--outline-width"),
        (&["--outline-width", "65"][..], "--outline-width"),
        (&["--outline-width", "nan"][..], "--outline-width"),
        (&["--outline-method", "grow"][..], "--outline-method"),
        (&["--outline-blur", "17"][..], "--outline-blur"),
        (&["--outline-blur", "-1"][..], "--outline-blur"),
    ] {
        let mut args = common_args.to_vec();
        args.extend_from_slice(value);
        let err = common::run_err(&args);
        assert_eq!(err.trim_end().lines().count(), 1, "{value:?}: {err}");
        assert!(err.contains(mentions), "{value:?}: '{mentions}' not in {err}");
    }
}

#[test]
fn blurred_outline_emulated_equals_reference() {
    let gpu = common::gpu();
    let outline = builtin_scene("outline").expect("scene");
    let cases: [(&[&str], OutlineMethod, u32); 4] = [
        (&["box"], OutlineMethod::Extrude, 4),
        // The torus in front of the box is not selected; the box and sphere intersect.
        (&["box", "sphere"], OutlineMethod::Extrude, 2),
        (&["box", "sphere", "torus knot"], OutlineMethod::Scale, 6),
        (&["torus", "ground"], OutlineMethod::Scale, 1),
    ];
    for (names, method, radius) in cases {
        let cartoon = CartoonOptions {
            select: names.iter().map(|s| s.to_string()).collect(),
            outline_blur: radius,
            ..options(method, 4.0)
        };
        let reference = render(&gpu, &outline, StencilMode::Reference, &cartoon);
        let emulated = render(&gpu, &outline, StencilMode::Emulated, &cartoon);
        let label = format!("{names:?} {method:?} blur {radius}");
        let differing = rgb_differences(&emulated, &reference);
        assert_eq!(differing, 0, "{label}: {differing} pixels differ");
        // Not vacuous: the blurred outline changes the frame, and differs from the sharp one.
        let sharp =
            render(&gpu, &outline, StencilMode::Emulated, &CartoonOptions { outline_blur: 0, ..cartoon.clone() });
        assert!(rgb_differences(&emulated, &sharp) > 100, "{label}: the blur changes nothing");
    }
    common::assert_no_validation_messages(&gpu);
}

/// A cube seen face-on: its outline's edges are straight, so along the middle row (column) the
/// box blur of radius R spreads the sharp outline by exactly R pixels outwards, with a
/// coverage of about 1/(2R + 1) at the last one; the selected face itself is never covered.
#[test]
fn blurred_outline_extends_the_sharp_one_by_the_radius() {
    let gpu = common::gpu();
    let scene = face_on_scene(shapes::cube(1.0), Mat4::IDENTITY);
    let background = common::srgb8(scene.background);
    let sharp_options = options(OutlineMethod::Extrude, 4.0);
    let sharp = render(&gpu, &scene, StencilMode::Emulated, &sharp_options);
    let (mid_x, mid_y) = (SIZE.0 / 2, SIZE.1 / 2);
    // First non-background pixel from the left of the middle row, from the top of the middle
    // column.
    let first_left = |image: &RgbaImage| (0..SIZE.0).find(|&x| image.get_pixel(x, mid_y).0[..3] != background);
    let first_top = |image: &RgbaImage| (0..SIZE.1).find(|&y| image.get_pixel(mid_x, y).0[..3] != background);
    let (sharp_left, sharp_top) = (first_left(&sharp).expect("outline"), first_top(&sharp).expect("outline"));
    assert_eq!(sharp.get_pixel(sharp_left, mid_y).0[..3], sharp_options.outline_colour, "the sharp outline's edge");
    for radius in [1u32, 3, 6] {
        let cartoon = CartoonOptions { outline_blur: radius, ..sharp_options.clone() };
        for stencil in [StencilMode::Emulated, StencilMode::Reference] {
            let blurred = render(&gpu, &scene, stencil, &cartoon);
            let label = format!("blur {radius} {stencil:?}");
            assert_eq!(first_left(&blurred), Some(sharp_left - radius), "{label}: along the middle row");
            assert_eq!(first_top(&blurred), Some(sharp_top - radius), "{label}: down the middle column");
            // From there to the face, every pixel is tinted.
            let face = (0..SIZE.0).find(|&x| sharp.get_pixel(x, mid_y).0[3] == 255).expect("the face");
            for x in sharp_left - radius..face {
                assert_ne!(blurred.get_pixel(x, mid_y).0[..3], background, "{label}: ({x}, {mid_y}) untinted");
            }
            // The selected face is as the sharp frame draws it.
            for (p, q) in blurred.pixels().zip(sharp.pixels()).filter(|(_, q)| q.0[3] == 255) {
                assert_eq!(p.0[..3], q.0[..3], "{label}: the blur covers the selection");
            }
        }
    }
    common::assert_no_validation_messages(&gpu);
}
