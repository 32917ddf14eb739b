//! Cartoon rendering: the stencil-free outline is proven against the real stencil pixel for
//! pixel; ink lines are measured in the image against their analytic position and width; the
//! shader and hull methods put dark ink on the silhouette.

use crate::common::{self, technique};

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use image::RgbaImage;
use nostencil::error::Result;
use nostencil::mesh::{shapes, MeshData};
use nostencil::Gpu;
use nostencil::StencilMode;
use nostencil::{builtin_scene, Camera, Light, Scene};
use nostencil::{
    render_scene, stats::CartoonStats, CartoonOptions, RenderOptions, SilhouetteMethod, Technique, TechniqueFrame,
};

const SIZE: (u32, u32) = (160, 120);
/// The ink colour of the silhouette and toon techniques, (0.04, 0.04, 0.06) in 8 bits.
/// The ink colour as the sRGB frame stores it.
fn ink() -> [u8; 3] {
    common::srgb8(nostencil::technique::ink::renderer::INK_COLOUR.truncate())
}

fn render_frame(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    technique: Technique,
    options: &CartoonOptions,
    size: (u32, u32),
) -> Result<TechniqueFrame> {
    let options = RenderOptions {
        width: size.0,
        height: size.1,
        stencil,
        technique,
        cartoon: options.clone(),
        ..Default::default()
    };
    render_scene(gpu, scene, &options)
}

fn render(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    technique: Technique,
    options: &CartoonOptions,
    size: (u32, u32),
) -> (RgbaImage, CartoonStats) {
    let frame = render_frame(gpu, scene, stencil, technique, options, size).expect("cartoon frame");
    let stats = frame.stats::<CartoonStats>().expect("cartoon stats").clone();
    (frame.output.image, stats)
}

fn rgb_differences(a: &RgbaImage, b: &RgbaImage) -> usize {
    a.chunks_exact(4).zip(b.chunks_exact(4)).filter(|(p, q)| p[..3] != q[..3]).count()
}

fn count_rgb(image: &RgbaImage, rgb: [u8; 3]) -> usize {
    image.chunks_exact(4).filter(|p| p[..3] == rgb).count()
}

#[test]
fn outline_emulated_equals_reference_for_one_and_several_overlapping_objects() {
    let gpu = common::gpu();
    let outline = builtin_scene("outline").expect("scene");
    let default = builtin_scene("default").expect("scene");
    let cases: [(&Scene, &[&str]); 6] = [
        (&outline, &[]),
        (&outline, &["box"]),
        // The box and the sphere intersect: no outline between them.
        (&outline, &["box", "sphere"]),
        // The torus in front of the box is not selected: the box's outline crosses it.
        (&outline, &["box", "sphere", "torus knot"]),
        (&outline, &["box", "sphere", "torus knot", "torus", "ground"]),
        (&default, &["torus", "torus knot"]),
    ];
    let orange = CartoonOptions::default().outline_colour;
    for (scene, names) in cases {
        let options =
            CartoonOptions { select: names.iter().map(|s| s.to_string()).collect(), ..CartoonOptions::default() };
        let (reference, _) = render(&gpu, scene, StencilMode::Reference, technique("outline"), &options, SIZE);
        let (emulated, stats) = render(&gpu, scene, StencilMode::Emulated, technique("outline"), &options, SIZE);
        let label = format!("{} {names:?}", scene.name);
        assert!(!stats.selected.is_empty(), "{label}: nothing selected");
        let outline_pixels = count_rgb(&reference, orange);
        assert!(outline_pixels > 100, "{label}: the reference shows {outline_pixels} outline pixels");
        let differing = rgb_differences(&emulated, &reference);
        assert_eq!(differing, 0, "{label}: {differing} pixels differ");
        // Alpha is the emulated stencil: 1 exactly on the visible selected surfaces.
        let marked = emulated.chunks_exact(4).filter(|p| p[3] == 255).count();
        assert!(marked > 100, "{label}: {marked} pixels marked");
        assert!(emulated.chunks_exact(4).all(|p| p[3] == 0 || p[3] == 255), "{label}: alpha not 0/1");
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn outline_never_covers_a_selected_surface_and_hugs_the_selected_object() {
    // Every outline pixel is off the visible selected surface (alpha 0 there) and within the
    // outline width of the selected object's whole silhouette (rendered alone: the outline
    // copy is drawn with the depth test off, so it also paints over the hidden part of the
    // object, as the document's stencil version does).
    let gpu = common::gpu();
    let scene = builtin_scene("outline").expect("scene");
    let one = CartoonOptions { select: vec!["box".into()], ..CartoonOptions::default() };
    let (image, _) = render(&gpu, &scene, StencilMode::Emulated, technique("outline"), &one, SIZE);
    let mut alone_scene = scene.clone();
    alone_scene.objects.retain(|o| o.name == "box");
    let (alone, _) = render(&gpu, &alone_scene, StencilMode::Emulated, technique("outline"), &one, SIZE);
    let orange = one.outline_colour;
    let (w, h) = (image.width() as i32, image.height() as i32);
    let reach = one.outline_width.ceil() as i32 + 1;
    for y in 0..h {
        for x in 0..w {
            let p = image.get_pixel(x as u32, y as u32).0;
            if p[..3] != orange {
                continue;
            }
            assert_eq!(p[3], 0, "outline drawn over the selected surface at ({x}, {y})");
            let near_selection = (-reach..=reach).any(|dy| {
                (-reach..=reach).any(|dx| {
                    let (sx, sy) = (x + dx, y + dy);
                    sx >= 0 && sy >= 0 && sx < w && sy < h && alone.get_pixel(sx as u32, sy as u32).0[3] == 255
                })
            });
            assert!(near_selection, "outline pixel ({x}, {y}) is not within {reach} px of the selection");
        }
    }
    // Alone, the outline is a ring: every pixel next to the box (1 px out) is outline.
    let mut ring = 0;
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let inside = |x: i32, y: i32| alone.get_pixel(x as u32, y as u32).0[3] == 255;
            if !inside(x, y) && (inside(x - 1, y) || inside(x + 1, y) || inside(x, y - 1) || inside(x, y + 1)) {
                assert_eq!(alone.get_pixel(x as u32, y as u32).0[..3], orange, "({x}, {y}) next to the box");
                ring += 1;
            }
        }
    }
    assert!(ring > 50, "{ring} ring pixels");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn unknown_selection_is_refused_with_the_objects_names() {
    let gpu = common::gpu();
    let scene = builtin_scene("outline").expect("scene");
    let options = CartoonOptions { select: vec!["teapot".into()], ..CartoonOptions::default() };
    let error = render_frame(&gpu, &scene, StencilMode::Emulated, technique("outline"), &options, (64, 64))
        .err()
        .expect("unknown object")
        .to_string();
    assert!(error.contains("teapot") && error.contains("sphere"), "{error}");
    let bad_width = CartoonOptions { line_width: 0.0, ..CartoonOptions::default() };
    assert!(bad_width.check().is_err());
    common::assert_no_validation_messages(&gpu);
}

/// A scene with one object in front of a camera on the +Z axis looking at the origin.
fn face_on_scene(mesh: MeshData, transform: Mat4) -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO);
    let light = Light::Directional { direction: Vec3::new(0.0, 0.0, -1.0) };
    let mut scene = Scene { background: Vec3::new(0.9, 0.9, 0.9), ..Scene::empty("face-on", camera, light) };
    let mesh = scene.add_mesh("shape", mesh);
    scene.add_object("shape", mesh, transform, Vec3::new(0.3, 0.5, 0.8), false);
    scene
}

/// A unit square in the z = 0 plane facing +Z: open, its outline is four boundary edges.
fn square() -> MeshData {
    nostencil::mesh::shapes::quad(Vec3::ZERO, Vec3::Z, glam::Vec2::ONE)
}

/// Rows of column `x` within 10 rows of `y` painted in ink.
fn ink_rows(image: &RgbaImage, x: u32, y: f32) -> Vec<u32> {
    (0..image.height()).filter(|&r| (r as f32 - y).abs() < 10.0 && image.get_pixel(x, r).0[..3] == ink()).collect()
}

#[test]
fn ink_line_width_in_the_image_is_the_requested_width() {
    let gpu = common::gpu();
    let size = (128, 128);
    // A square's top edge is a boundary: the line is centred on it. A cube's front face top edge
    // seen face-on is a silhouette: the line grows outwards (up) from it.
    let cases = [
        ("square boundary", square(), Vec3::new(0.0, 0.5, 0.0), false),
        ("cube silhouette", shapes::cube(1.0), Vec3::new(0.0, 0.5, 0.5), true),
    ];
    for (label, mesh, edge, outward) in &cases {
        // Lift the shape until its edge lands a quarter pixel below a pixel border, so that no
        // band border below falls on a pixel centre.
        let at = |lift: f32| {
            let scene = face_on_scene(mesh.clone(), Mat4::from_translation(Vec3::new(0.0, lift, 0.0)));
            let y = common::pixel_y(&scene, *edge + Vec3::new(0.0, lift, 0.0), size);
            (scene, y)
        };
        let lift = (0..200).map(|i| 0.1 + i as f32 * 0.001).find(|&l| (at(l).1.fract() - 0.25).abs() < 0.05);
        let (scene, y) = at(lift.expect("a lift that puts the edge at .25"));
        let scene = &scene;
        for width in [1.0f32, 2.0, 3.0, 5.0] {
            let options = CartoonOptions { line_width: width, ..CartoonOptions::default() };
            let (image, stats) = render(&gpu, scene, StencilMode::Emulated, technique("silhouette"), &options, size);
            let (top, bottom) = if *outward { (y - width, y) } else { (y - 0.5 * width, y + 0.5 * width) };
            // The analytic band must not put a pixel centre on its border (that would test the
            // tie rule, not the width).
            for border in [top, bottom] {
                assert!((border - border.floor() - 0.5).abs() > 0.02, "{label}: border {border} on a centre");
            }
            let expected = common::rows_between(top, bottom);
            assert_eq!(expected.len(), width as usize);
            let measured = ink_rows(&image, size.0 / 2, y);
            assert_eq!(measured, expected, "{label} width {width}: edge at y = {y} ({stats:?})");
        }
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn ink_lines_sit_on_the_sphere_silhouette_without_gaps() {
    // A sphere face-on: its silhouette is a circle of known radius on screen. Every ray from
    // the centre crosses ink just outside that circle, and no ink lies inside it.
    let gpu = common::gpu();
    let size = (128, 128);
    let scene = face_on_scene(shapes::uv_sphere(24, 48).expect("sphere"), Mat4::IDENTITY);
    let options = CartoonOptions { line_width: 2.0, ..CartoonOptions::default() };
    let (image, stats) = render(&gpu, &scene, StencilMode::Emulated, technique("silhouette"), &options, size);
    assert!(stats.silhouette_edges >= 48, "{stats:?}");
    // The contour seen from distance d of a unit sphere: radius sin(asin(1/d)) at depth 1/d,
    // i.e. tangent angle asin(1/5) from the axis.
    let focal = 0.5 * size.1 as f32 / (0.5 * scene.camera.fov_y_radians).tan();
    let radius_px = focal * (1.0f32 / 5.0).asin().tan();
    let centre = Vec2::new(size.0 as f32 * 0.5, size.1 as f32 * 0.5);
    for step in 0..72 {
        let angle = step as f32 * std::f32::consts::TAU / 72.0;
        let dir = Vec2::new(angle.cos(), angle.sin());
        let ink_at: Vec<f32> = (0..(radius_px as i32 + 8) * 4)
            .map(|i| i as f32 * 0.25)
            .filter(|r| {
                let p = centre + dir * *r;
                image.get_pixel(p.x as u32, p.y as u32).0[..3] == ink()
            })
            .collect();
        assert!(!ink_at.is_empty(), "no ink at {angle} rad");
        let (first, last) = (ink_at[0], ink_at[ink_at.len() - 1]);
        // Tessellation (48 segments) puts the polygon up to 0.3% inside the circle.
        assert!(first > radius_px - 1.5 && last < radius_px + 3.5, "{angle} rad: ink from {first} to {last}");
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn every_ink_method_darkens_the_silhouette_and_toon_shading_has_bands() {
    let gpu = common::gpu();
    let scene = face_on_scene(shapes::uv_sphere(24, 48).expect("sphere"), Mat4::IDENTITY);
    let size = (96, 96);
    // Within 25 of the ink (filtered line edges blend towards the surface).
    let ink = ink();
    let dark = |p: [u8; 4]| (0..3).all(|c| p[c] <= ink[c].saturating_add(25));
    for &method in SilhouetteMethod::ALL {
        let options = CartoonOptions { silhouette: method, line_width: 3.0, ..CartoonOptions::default() };
        for technique in [technique("silhouette"), technique("toon")] {
            let (image, _) = render(&gpu, &scene, StencilMode::Emulated, technique, &options, size);
            // The sphere's centre is lit, its contour (radius ~ 21 px) is dark.
            assert!(!dark(image.get_pixel(48, 48).0), "{method:?} {technique:?}: centre is dark");
            let dark_on_contour = (0..36)
                .filter(|i| {
                    let a = *i as f32 * std::f32::consts::TAU / 36.0;
                    (36..52).any(|r| {
                        let r = r as f32 * 0.5;
                        let (x, y) = (48.0 + a.cos() * r, 48.0 + a.sin() * r);
                        dark(image.get_pixel(x as u32, y as u32).0)
                    })
                })
                .count();
            assert_eq!(dark_on_contour, 36, "{method:?} {technique:?}: contour not inked all round");
        }
    }
    // The toon ramp has three levels: a toon frame without ink shows at most three shades of
    // the albedo on the sphere (plus the background).
    let options = CartoonOptions { silhouette: SilhouetteMethod::Hull, line_width: 0.5, ..CartoonOptions::default() };
    let (image, _) = render(&gpu, &scene, StencilMode::Emulated, technique("toon"), &options, size);
    let mut colours: Vec<[u8; 3]> = image.chunks_exact(4).map(|p| [p[0], p[1], p[2]]).collect();
    colours.sort();
    colours.dedup();
    assert!(colours.len() <= 6, "{} colours: {colours:?}", colours.len());
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn ink_passes_are_measured_one_per_edge_class() {
    let gpu = common::gpu();
    let scene = builtin_scene("default").expect("scene");
    let frame = render_frame(&gpu, &scene, StencilMode::Emulated, technique("toon"), &CartoonOptions::default(), SIZE)
        .expect("frame");
    let names: Vec<&str> = frame.output.counters.passes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["scene", "ink silhouette", "ink crease", "ink boundary"]);
    for pass in &frame.output.counters.passes {
        assert!(pass.draws <= scene.objects.len() as u32, "{}: {} draws", pass.name, pass.draws);
    }
    let stats = frame.stats::<CartoonStats>().expect("cartoon stats");
    assert!(stats.silhouette_edges > 0 && stats.crease_edges > 0 && stats.boundary_edges > 0, "{stats:?}");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn crease_lines_of_a_cube_are_unbroken_and_stay_on_the_edges() {
    // A cube seen from a corner: the three edges at the nearest corner are 90 degree creases
    // between visible faces, drawn centred and depth tested against those very faces. Every
    // pixel an edge passes through must be ink (no z-fighting gaps), and face centres must not.
    let gpu = common::gpu();
    let size = (128, 128);
    let mut scene = face_on_scene(shapes::cube(1.0), Mat4::IDENTITY);
    scene.camera = Camera::look_at(Vec3::new(2.2, 1.9, 2.6), Vec3::ZERO);
    let options = CartoonOptions { line_width: 2.0, ..CartoonOptions::default() };
    let (image, stats) = render(&gpu, &scene, StencilMode::Emulated, technique("silhouette"), &options, size);
    assert_eq!((stats.silhouette_edges, stats.crease_edges), (6, 6), "{stats:?}");
    let view_proj = scene.camera.view_projection(1.0);
    let to_pixel = |p: Vec3| {
        let c = view_proj * p.extend(1.0);
        Vec2::new((c.x / c.w + 1.0) * 0.5 * size.0 as f32, (c.y / c.w + 1.0) * 0.5 * size.1 as f32)
    };
    let corner = Vec3::splat(0.5);
    for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
        for i in 1..40 {
            let p = to_pixel(corner - axis * (i as f32 / 40.0));
            assert_eq!(image.get_pixel(p.x as u32, p.y as u32).0[..3], ink(), "edge along {axis} at {p}");
        }
        let face_centre = to_pixel(corner - (Vec3::ONE - axis) * 0.5);
        assert_ne!(image.get_pixel(face_centre.x as u32, face_centre.y as u32).0[..3], ink(), "face {axis}");
    }
    common::assert_no_validation_messages(&gpu);
}
