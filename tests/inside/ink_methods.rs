//! The seed-002 ink methods measured against what they must draw, computed on the CPU: the
//! alpha test's ring on a sphere is where N.V < the reference value.

use crate::common::{self, technique};

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use image::RgbaImage;
use nostencil::mesh::{shapes, MeshData};
use nostencil::technique::light_loop::PlannedLight;
use nostencil::Gpu;
use nostencil::StencilMode;
use nostencil::{render_scene, CartoonOptions, RenderOptions, SilhouetteMethod, Technique};
use nostencil::{Camera, Light, Scene};

/// The ink colour as the sRGB frame stores it.
fn ink() -> [u8; 3] {
    common::srgb8(nostencil::technique::ink::renderer::INK_COLOUR.truncate())
}

/// Camera distance from the origin, on +Z.
const EYE_DISTANCE: f32 = 5.0;

/// A scene of `meshes` (mesh, transform, colour) seen by a camera on +Z looking at the origin.
fn face_on_scene(meshes: &[(MeshData, Mat4, Vec3)]) -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, EYE_DISTANCE), Vec3::ZERO);
    let light = Light::Directional { direction: Vec3::new(0.0, 0.0, -1.0) };
    let mut scene = Scene { background: Vec3::new(0.9, 0.9, 0.9), ..Scene::empty("face-on", camera, light) };
    for (i, (mesh, transform, colour)) in meshes.iter().enumerate() {
        let name = format!("shape {i}");
        let mesh = scene.add_mesh(&name, mesh.clone());
        scene.add_object(&name, mesh, *transform, *colour, false);
    }
    scene
}

fn unit_sphere() -> MeshData {
    shapes::uv_sphere(32, 64).expect("sphere")
}

fn render(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    technique: Technique,
    options: &CartoonOptions,
    size: (u32, u32),
) -> RgbaImage {
    let options = RenderOptions {
        width: size.0,
        height: size.1,
        stencil: StencilMode::Emulated,
        technique,
        cartoon: options.clone(),
        ..Default::default()
    };
    render_scene(gpu, scene, &options).expect("ink frame").output.image
}

/// Pixels per unit of tan(angle off the view axis).
fn focal_px(scene: &Scene, height: u32) -> f32 {
    0.5 * height as f32 / (0.5 * scene.camera.fov_y_radians).tan()
}

/// On screen, the radius (pixels) of the circle of a unit sphere at the origin, seen from
/// distance `d` on its axis, where N.V = `t`. A point at angle `theta` from the axis is
/// (sin, 0, cos); N.V = (d cos - 1) / |E - P| falls from 1 on the axis to 0 on the contour
/// (cos = 1/d), so bisection finds it.
fn radius_where_n_dot_v_is(t: f32, d: f32, focal: f32) -> f32 {
    let n_dot_v = |theta: f32| {
        let (s, c) = theta.sin_cos();
        (d * c - 1.0) / (s * s + (d - c) * (d - c)).sqrt()
    };
    let (mut lo, mut hi) = (0.0f32, (1.0 / d).acos());
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if n_dot_v(mid) > t {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (s, c) = lo.sin_cos();
    focal * s / (d - c)
}

/// Along `rays` rays from the image centre, sampled every quarter pixel out to `reach`: the
/// first and last radius whose pixel is ink (None: no ink on that ray).
fn ink_span_per_ray(image: &RgbaImage, rays: u32, reach: f32) -> Vec<Option<(f32, f32)>> {
    let centre = Vec2::new(image.width() as f32 * 0.5, image.height() as f32 * 0.5);
    (0..rays)
        .map(|step| {
            let angle = step as f32 * std::f32::consts::TAU / rays as f32;
            let dir = Vec2::new(angle.cos(), angle.sin());
            let ink_at: Vec<f32> = (0..(reach * 4.0) as i32)
                .map(|i| i as f32 * 0.25)
                .filter(|r| {
                    let p = centre + dir * *r;
                    image.get_pixel(p.x as u32, p.y as u32).0[..3] == ink()
                })
                .collect();
            Some((*ink_at.first()?, *ink_at.last()?))
        })
        .collect()
}

#[test]
fn alpha_test_ring_on_a_sphere_is_where_n_dot_v_is_below_the_reference() {
    let gpu = common::gpu();
    let size = (160, 160);
    let scene = face_on_scene(&[(unit_sphere(), Mat4::IDENTITY, Vec3::new(0.3, 0.5, 0.8))]);
    let focal = focal_px(&scene, size.1);
    let contour = radius_where_n_dot_v_is(0.0, EYE_DISTANCE, focal);
    let mut thickness = Vec::new();
    for reference in [0.35f32, 0.5, 0.7, 0.9] {
        let inner = radius_where_n_dot_v_is(reference, EYE_DISTANCE, focal);
        let options = CartoonOptions {
            silhouette: SilhouetteMethod::AlphaTest,
            alpha_ref: reference,
            ..CartoonOptions::default()
        };
        for technique in [technique("silhouette"), technique("toon")] {
            let image = render(&gpu, &scene, technique, &options, size);
            let label = format!("{} alpha-ref {reference}", technique.name());
            for (ray, span) in ink_span_per_ray(&image, 72, contour + 4.0).into_iter().enumerate() {
                let (first, last) = span.unwrap_or_else(|| panic!("{label}: no ink on ray {ray}"));
                // A pixel holds the ray's point within 0.71 px of its centre; the 64-segment
                // polygon lies up to 0.12% inside the sphere.
                assert!((first - inner).abs() < 1.25, "{label}, ray {ray}: ink from {first}, N.V = ref at {inner}");
                assert!((last - contour).abs() < 1.25, "{label}, ray {ray}: ink to {last}, contour at {contour}");
            }
            thickness.push(contour - inner);
        }
    }
    // Not vacuous: the references give rings from 2 to over 10 pixels.
    assert!(thickness[0] < 3.0 && thickness[thickness.len() - 1] > 10.0, "{thickness:?}");
    common::assert_no_validation_messages(&gpu);
}

fn is_ink(p: &image::Rgba<u8>) -> bool {
    p.0[..3] == ink()
}

#[test]
fn extrusion_rings_a_sphere_like_the_hull() {
    let gpu = common::gpu();
    let size = (160, 160);
    let scene = face_on_scene(&[(unit_sphere(), Mat4::IDENTITY, Vec3::new(0.3, 0.5, 0.8))]);
    let contour = radius_where_n_dot_v_is(0.0, EYE_DISTANCE, focal_px(&scene, size.1));
    for width in [2.0f32, 4.0] {
        let options = |method| CartoonOptions { silhouette: method, line_width: width, ..CartoonOptions::default() };
        let extrusion = render(&gpu, &scene, technique("silhouette"), &options(SilhouetteMethod::Extrusion), size);
        for (ray, span) in ink_span_per_ray(&extrusion, 72, contour + width + 4.0).into_iter().enumerate() {
            let (first, last) = span.unwrap_or_else(|| panic!("width {width}: no ink on ray {ray}"));
            // The copy is pushed out by `width` pixels along the normal, which is across the
            // view ray at the contour; pixels hold their ray point within 0.71 px.
            assert!((first - contour).abs() < 1.25, "width {width}, ray {ray}: ink from {first}, contour {contour}");
            assert!((last - contour - width).abs() < 1.25, "width {width}, ray {ray}: ink to {last}");
        }
        // Alone, nothing is in front of the copy or drawn before it: the same ring as the
        // inverted hull's (a closed copy's front and back faces cover the same pixels).
        let hull = render(&gpu, &scene, technique("silhouette"), &options(SilhouetteMethod::Hull), size);
        let differing = extrusion.pixels().zip(hull.pixels()).filter(|(a, b)| a.0[..3] != b.0[..3]).count();
        assert_eq!(differing, 0, "width {width}: extrusion and hull differ on a lone sphere");
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn extruded_copy_with_depth_off_shows_through_an_object_in_front_and_the_hull_does_not() {
    // Sphere A in front (drawn first), sphere B behind it and to the right. The seed's
    // extrusion draws B's copy with the depth test off after A: its ring paints over A's
    // body. The inverted hull's copy is depth tested: A hides it.
    let gpu = common::gpu();
    let size = (160, 120);
    let a = (unit_sphere(), Mat4::from_translation(Vec3::new(-0.3, 0.0, 1.5)), Vec3::new(0.3, 0.5, 0.8));
    let b = (unit_sphere(), Mat4::from_translation(Vec3::new(1.0, 0.0, -1.0)), Vec3::new(0.8, 0.5, 0.3));
    let both = face_on_scene(&[a.clone(), b.clone()]);
    let options = |method| CartoonOptions { silhouette: method, line_width: 3.0, ..CartoonOptions::default() };
    let extrusion = options(SilhouetteMethod::Extrusion);
    // Masks from each sphere rendered alone: B's ring, and A's body well inside its ring.
    let b_alone = render(&gpu, &face_on_scene(&[b]), technique("silhouette"), &extrusion, size);
    let a_alone = render(&gpu, &face_on_scene(&[a]), technique("silhouette"), &extrusion, size);
    let background = common::srgb8(both.background);
    let (w, h) = (size.0 as i32, size.1 as i32);
    let a_inside = |x: i32, y: i32| {
        (-5..=5).all(|dy| {
            (-5..=5).all(|dx| {
                let (sx, sy) = (x + dx, y + dy);
                sx >= 0 && sy >= 0 && sx < w && sy < h && {
                    let p = a_alone.get_pixel(sx as u32, sy as u32);
                    !is_ink(p) && p.0[..3] != background
                }
            })
        })
    };
    let crossing: Vec<(u32, u32)> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| is_ink(b_alone.get_pixel(x as u32, y as u32)) && a_inside(x, y))
        .map(|(x, y)| (x as u32, y as u32))
        .collect();
    assert!(crossing.len() > 20, "B's ring crosses A's body at only {} pixels", crossing.len());
    let with_extrusion = render(&gpu, &both, technique("silhouette"), &extrusion, size);
    let with_hull = render(&gpu, &both, technique("silhouette"), &options(SilhouetteMethod::Hull), size);
    for &(x, y) in &crossing {
        assert!(is_ink(with_extrusion.get_pixel(x, y)), "extrusion: B's ring hidden by A at ({x}, {y})");
        assert_eq!(with_hull.get_pixel(x, y), a_alone.get_pixel(x, y), "hull: A's body changed at ({x}, {y})");
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn extrusion_and_hull_plans_differ_in_passes_and_depth_and_cull_state() {
    use ash::vk;
    let plan = |method| {
        let options = RenderOptions {
            technique: technique("silhouette"),
            cartoon: CartoonOptions { silhouette: method, ..CartoonOptions::default() },
            ..Default::default()
        };
        technique("silhouette").plan(&options, &PlannedLight::default_lights()).expect("plan")
    };
    let hull = plan(SilhouetteMethod::Hull);
    let names = |p: &nostencil::render::plan::PassPlan| p.passes.iter().map(|p| p.name.to_string()).collect::<Vec<_>>();
    assert_eq!(names(&hull), ["scene", "inverted hull"]);
    let hull_copy = hull.passes[1].pipeline().expect("hull pipeline");
    assert_eq!((hull_copy.fixed.depth.compare, hull_copy.fixed.depth.write), (Some(vk::CompareOp::LESS), true));
    assert_eq!(hull_copy.fixed.raster.cull, vk::CullModeFlags::FRONT);

    // One pass binding both pipelines: per object, the copy and then the object.
    let extrusion = plan(SilhouetteMethod::Extrusion);
    assert_eq!(names(&extrusion), ["extruded copy, then object"]);
    let copy = extrusion.passes[0].pipelines.iter().find(|p| p.name == "extruded copy (depth off)").expect("copy");
    assert_eq!((copy.fixed.depth.compare, copy.fixed.depth.write), (None, false));
    assert_eq!(copy.fixed.raster.cull, vk::CullModeFlags::BACK);
    let scene = extrusion.passes[0].pipeline().expect("scene pipeline");
    assert_eq!(
        (scene.name, scene.fixed.depth.compare, scene.fixed.depth.write),
        ("scene", Some(vk::CompareOp::LESS), true)
    );
}

/// A unit square in the z = 0 plane facing +Z: open, its outline is four boundary edges.
fn square() -> MeshData {
    nostencil::mesh::shapes::quad(Vec3::ZERO, Vec3::Z, glam::Vec2::ONE)
}

/// Two quads folded 90 degrees along the x axis (the ridge, nearest the eye), both facing +Z:
/// the ridge is a crease between faces that share its vertices (no seam), the rest boundary.
fn ridge() -> MeshData {
    let s = std::f32::consts::FRAC_1_SQRT_2;
    MeshData {
        positions: vec![
            Vec3::new(-0.5, 0.0, 0.0),
            Vec3::new(0.5, 0.0, 0.0),
            Vec3::new(0.5, 0.5, -0.5),
            Vec3::new(-0.5, 0.5, -0.5),
            Vec3::new(0.5, -0.5, -0.5),
            Vec3::new(-0.5, -0.5, -0.5),
        ],
        normals: vec![
            Vec3::Z,
            Vec3::Z,
            Vec3::new(0.0, s, s),
            Vec3::new(0.0, s, s),
            Vec3::new(0.0, -s, s),
            Vec3::new(0.0, -s, s),
        ],
        uvs: vec![Vec2::ZERO; 6],
        indices: vec![0, 1, 2, 0, 2, 3, 0, 4, 1, 0, 5, 4],
    }
}

#[test]
fn each_edge_class_is_drawn_in_its_own_width_and_colour() {
    use nostencil::InkStyle;
    let gpu = common::gpu();
    let size = (128, 128);
    // Widths and colours all different (pure primaries: the sRGB frame stores them exactly).
    let styles = [
        InkStyle { width: Some(4.0), colour: Some([255, 0, 0]) },
        InkStyle { width: Some(3.0), colour: Some([0, 255, 0]) },
        InkStyle { width: Some(1.0), colour: Some([0, 0, 255]) },
    ];
    let [silhouette, crease, boundary] = styles.map(Some);
    let ink = nostencil::technique::InkStyles { silhouette, crease, boundary };
    let options = CartoonOptions { ink, line_width: 2.0, ..CartoonOptions::default() };
    // (class, mesh, a point of a horizontal edge of that class, one-sided outward)
    let cases = [
        (0, shapes::cube(1.0), Vec3::new(0.0, 0.5, 0.5), true),
        (1, ridge(), Vec3::ZERO, false),
        (2, square(), Vec3::new(0.0, 0.5, 0.0), false),
    ];
    for (class, mesh, edge, outward) in cases {
        // Lift the shape until its edge lands a quarter pixel below a pixel border, so that no
        // band border falls on a pixel centre.
        let at = |lift: f32| {
            let transform = Mat4::from_translation(Vec3::new(0.0, lift, 0.0));
            let scene = face_on_scene(&[(mesh.clone(), transform, Vec3::new(0.9, 0.8, 0.2))]);
            let y = common::pixel_y(&scene, edge + Vec3::new(0.0, lift, 0.0), size);
            (scene, y)
        };
        let lift = (0..200).map(|i| 0.1 + i as f32 * 0.001).find(|&l| (at(l).1.fract() - 0.25).abs() < 0.05);
        let (scene, y) = at(lift.expect("a lift that puts the edge at .25"));
        let image = render(&gpu, &scene, technique("silhouette"), &options, size);
        let (width, colour) = (styles[class].width.unwrap_or(0.0), styles[class].colour.unwrap_or_default());
        let (top, bottom) = if outward { (y - width, y) } else { (y - 0.5 * width, y + 0.5 * width) };
        let expected = common::rows_between(top, bottom);
        assert_eq!(expected.len(), width as usize);
        let measured: Vec<u32> = (0..size.1)
            .filter(|&r| (r as f32 - y).abs() < 8.0 && image.get_pixel(size.0 / 2, r).0[..3] == colour)
            .collect();
        assert_eq!(measured, expected, "class {class}: edge at y = {y}, colour {colour:?}");
    }
    // The GPU methods draw silhouettes only, in the silhouette's style.
    let scene = face_on_scene(&[(unit_sphere(), Mat4::IDENTITY, Vec3::new(0.3, 0.5, 0.8))]);
    for method in [SilhouetteMethod::Hull, SilhouetteMethod::Extrusion, SilhouetteMethod::AlphaTest] {
        let image = render(
            &gpu,
            &scene,
            technique("silhouette"),
            &CartoonOptions { silhouette: method, ..options.clone() },
            size,
        );
        let red = image.pixels().filter(|p| p.0[..3] == [255, 0, 0]).count();
        assert!(red > 100, "{method:?}: {red} pixels of the silhouette colour");
        assert!(!image.pixels().any(is_ink), "{method:?}: default ink drawn");
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn ink_styles_parse_and_bad_ones_are_one_line_errors() {
    use nostencil::InkStyle;
    assert_eq!(InkStyle::parse("--ink-crease", "3").ok(), Some(InkStyle { width: Some(3.0), colour: None }));
    assert_eq!(
        InkStyle::parse("--ink-crease", "2.5,#FF8000").ok(),
        Some(InkStyle { width: Some(2.5), colour: Some([255, 128, 0]) })
    );
    assert_eq!(
        InkStyle::parse("--ink-crease", "#00ff00").ok(),
        Some(InkStyle { width: None, colour: Some([0, 255, 0]) })
    );
    for (args, mentions) in [
        (["--ink-silhouette", "wide"], "--ink-silhouette"),
        (["--ink-crease", "2,#12345"], "--ink-crease"),
        (["--ink-boundary", "100"], "--ink-boundary"),
        (["--alpha-ref", "2"], "--alpha-ref"),
        (["--seams", "materials"], "--seams"),
        (["--seams", "uv,colour"], "--seams"),
    ] {
        let mut all = vec!["profile", "--size", "32x32", "--scene", "outline", "--technique", "silhouette"];
        all.extend_from_slice(&args);
        let err = common::run_err(&all);
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(mentions), "'{mentions}' not in {err}");
    }
}

#[test]
fn ink_only_leaves_no_face_colour_only_background_and_ink() {
    // The seed's figure 5.1.1, middle: faces in the background colour, ink on top.
    let gpu = common::gpu();
    let size = (128, 96);
    for scene_name in ["duck", "default"] {
        let scene = nostencil::builtin_scene(scene_name).expect("scene");
        let background = common::srgb8(scene.background);
        for &method in SilhouetteMethod::ALL {
            let options = CartoonOptions { silhouette: method, ink_only: true, ..CartoonOptions::default() };
            for technique in [technique("silhouette"), technique("toon")] {
                let image = render(&gpu, &scene, technique, &options, size);
                // The shader method's ink is the rim ramp's black times the face colour.
                let ink = if method == SilhouetteMethod::Shader { [0, 0, 0] } else { ink() };
                let label = format!("{scene_name} {} {method:?}", technique.name());
                let stray: Vec<_> = image.pixels().filter(|p| p.0[..3] != background && p.0[..3] != ink).collect();
                assert!(stray.is_empty(), "{label}: {} pixels neither background nor ink: {:?}", stray.len(), stray[0]);
                let inked = image.pixels().filter(|p| p.0[..3] == ink).count();
                assert!(inked > 50, "{label}: {inked} ink pixels");
                // Without --ink-only the same frame shows face colours.
                let shaded = CartoonOptions { ink_only: false, ..options.clone() };
                let image = render(&gpu, &scene, technique, &shaded, size);
                let faces = image.pixels().filter(|p| p.0[..3] != background && p.0[..3] != ink).count();
                assert!(faces > 500, "{label}: shaded, only {faces} face pixels");
            }
        }
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn face_normals_and_creases_are_recomputed_only_for_deformed_meshes() {
    use nostencil::builtin_scene_at;
    use nostencil::stats::CartoonStats;
    let gpu = common::gpu();
    let rest = builtin_scene_at("default", 0.0).expect("scene");
    let walking = builtin_scene_at("default", 0.4).expect("scene");
    let skinned = rest.objects.iter().filter(|o| o.skin.is_some()).count();
    assert!(skinned > 0 && skinned < rest.objects.len(), "the default scene has rigid and skinned objects");
    let options = RenderOptions { width: 96, height: 72, technique: technique("silhouette"), ..Default::default() };
    let mut renderer = technique("silhouette").build(&gpu, &rest, &options).expect("renderer");
    let mut frame = |scene: &Scene| {
        let frame = renderer.frame_with(scene).expect("frame");
        (frame.stats::<CartoonStats>().expect("cartoon stats").clone(), frame.output.image)
    };
    // First frame: every object; the same pose again: none; a new pose: the skinned only.
    assert_eq!(frame(&rest).0.face_normal_updates, rest.objects.len());
    assert_eq!(frame(&rest).0.face_normal_updates, 0);
    let (posed, image) = frame(&walking);
    assert_eq!(posed.face_normal_updates, skinned);
    assert_eq!(frame(&walking).0.face_normal_updates, 0);
    // What was kept is right: a renderer built for the new pose draws the same edges and image.
    let fresh = render_scene(&gpu, &walking, &options).expect("fresh frame");
    let fresh_stats = fresh.stats::<CartoonStats>().expect("cartoon stats");
    assert_eq!(
        (posed.silhouette_edges, posed.crease_edges, posed.boundary_edges),
        (fresh_stats.silhouette_edges, fresh_stats.crease_edges, fresh_stats.boundary_edges)
    );
    let differing = image.pixels().zip(fresh.output.image.pixels()).filter(|(a, b)| a.0[..3] != b.0[..3]).count();
    assert_eq!(differing, 0, "kept normals and creases change the image");
    common::assert_no_validation_messages(&gpu);
}

/// The edges-method silhouette frame of `scene` with these ink styles and seams.
fn render_seams(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    size: (u32, u32),
    ink: nostencil::technique::InkStyles,
    seams: nostencil::Seams,
) -> nostencil::TechniqueFrame {
    let cartoon = CartoonOptions { ink, seams, ..CartoonOptions::default() };
    let options = RenderOptions {
        width: size.0,
        height: size.1,
        technique: technique("silhouette"),
        cartoon,
        ..Default::default()
    };
    render_scene(gpu, scene, &options).expect("frame")
}

#[test]
fn uv_seams_are_boundaries_when_asked_for() {
    use nostencil::technique::InkStyles;
    use nostencil::{InkStyle, Seams};
    let gpu = common::gpu();
    let size = (128, 128);
    // The sphere's u = 0 meridian (on +X) turned towards the eye: a UV seam down the middle of
    // the disc, with smooth normals across it.
    let turned = Mat4::from_rotation_y(-std::f32::consts::FRAC_PI_2);
    let scene = face_on_scene(&[(unit_sphere(), turned, Vec3::new(0.3, 0.5, 0.8))]);
    let blue = [0, 0, 255];
    let ink = InkStyles { boundary: Some(InkStyle { width: Some(2.0), colour: Some(blue) }), ..Default::default() };
    let radius = radius_where_n_dot_v_is(0.0, EYE_DISTANCE, focal_px(&scene, size.1));
    for (seams, expect_seam) in [(Seams { uv: true, ..Seams::default() }, true), (Seams::default(), false)] {
        let frame = render_seams(&gpu, &scene, size, ink, seams);
        let stats = frame.stats::<nostencil::stats::CartoonStats>().expect("stats");
        let image = &frame.output.image;
        // Every row across the middle of the disc crosses the seam in blue, within a pixel of
        // the centre column; without UV seams nothing is blue.
        let rows = (size.1 / 2 - (radius * 0.6) as u32)..(size.1 / 2 + (radius * 0.6) as u32);
        let crossed = rows
            .clone()
            .filter(|&y| (size.0 / 2 - 2..size.0 / 2 + 2).any(|x| image.get_pixel(x, y).0[..3] == blue))
            .count();
        let any_blue = image.pixels().filter(|p| p.0[..3] == blue).count();
        if expect_seam {
            assert_eq!(crossed, rows.len(), "UV seam not drawn down the disc ({stats:?})");
            assert!(stats.boundary_edges > 0, "{stats:?}");
        } else {
            assert_eq!((any_blue, stats.boundary_edges), (0, 0), "{stats:?}");
        }
    }
    common::assert_no_validation_messages(&gpu);
}

/// A unit sphere cut along its x = 0 meridians into two glTF primitives of one mesh (left and
/// right half, each with its own material and its own copy of every vertex), as a self-contained
/// .gltf.
fn two_material_sphere_gltf() -> String {
    use base64::Engine as _;
    let sphere = unit_sphere();
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for t in sphere.indices.chunks_exact(3) {
        let centroid: Vec3 = t.iter().map(|&i| sphere.positions[i as usize]).sum::<Vec3>() / 3.0;
        if centroid.x < 0.0 { &mut left } else { &mut right }.extend_from_slice(t);
    }
    let mut bytes: Vec<u8> = sphere.positions.iter().flat_map(|p| p.to_array()).flat_map(f32::to_le_bytes).collect();
    let normals_at = bytes.len();
    bytes.extend(sphere.normals.iter().flat_map(|n| n.to_array()).flat_map(f32::to_le_bytes));
    let left_at = bytes.len();
    bytes.extend(left.iter().flat_map(|i| i.to_le_bytes()));
    let right_at = bytes.len();
    bytes.extend(right.iter().flat_map(|i| i.to_le_bytes()));
    let data = base64::engine::general_purpose::STANDARD.encode(&bytes);
    let count = sphere.positions.len();
    let primitive = |indices: usize, material: usize| serde_json::json!({ "attributes": { "POSITION": 0, "NORMAL": 1 }, "indices": indices, "material": material });
    serde_json::json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [primitive(2, 0), primitive(3, 1)] }],
        "materials": [
            { "pbrMetallicRoughness": { "baseColorFactor": [0.8, 0.3, 0.2, 1.0] } },
            { "pbrMetallicRoughness": { "baseColorFactor": [0.2, 0.6, 0.3, 1.0] } }
        ],
        "buffers": [{ "byteLength": bytes.len(), "uri": format!("data:application/octet-stream;base64,{data}") }],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": normals_at },
            { "buffer": 0, "byteOffset": normals_at, "byteLength": left_at - normals_at },
            { "buffer": 0, "byteOffset": left_at, "byteLength": right_at - left_at },
            { "buffer": 0, "byteOffset": right_at, "byteLength": bytes.len() - right_at }
        ],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
              "min": [-1.0, -1.0, -1.0], "max": [1.0, 1.0, 1.0] },
            { "bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3" },
            { "bufferView": 2, "componentType": 5125, "count": left.len(), "type": "SCALAR" },
            { "bufferView": 3, "componentType": 5125, "count": right.len(), "type": "SCALAR" }
        ]
    })
    .to_string()
}

#[test]
fn material_seams_inside_a_gltf_mesh_are_boundaries_only_when_asked_for() {
    use nostencil::technique::InkStyles;
    use nostencil::{InkStyle, Seams};
    let gpu = common::gpu();
    let size = (128u32, 128u32);
    let dir = common::scratch_dir("ink-material-seams");
    let file = dir.join("two-material-sphere.gltf");
    std::fs::write(&file, two_material_sphere_gltf()).expect("write the test file");
    let mut scene = nostencil::scene_from_gltf(&file, 0.0).expect("the file loads");
    // Only the sphere: the loader's ground plane is open, its rim a boundary of its own.
    scene.objects.retain(|o| o.name != "ground");
    // The loader keeps both halves as one mesh instance: the ink sees one closed sphere.
    assert_eq!(scene.objects.len(), 2);
    assert!(scene.objects[0].mesh_instance.is_some(), "primitives of one mesh share an instance");
    assert_eq!(scene.objects[0].mesh_instance, scene.objects[1].mesh_instance);
    assert_eq!(scene.mesh_instances(), vec![vec![0, 1]]);
    // Seen face on from +Z, the front cut (x = 0, z > 0) runs down the middle of the disc.
    scene.camera = Camera::look_at(Vec3::new(0.0, 0.0, EYE_DISTANCE), Vec3::ZERO);
    scene.set_light(Light::Directional { direction: Vec3::new(0.0, 0.0, -1.0) });
    let blue = [0, 0, 255];
    let ink = InkStyles { boundary: Some(InkStyle { width: Some(2.0), colour: Some(blue) }), ..Default::default() };
    let radius = radius_where_n_dot_v_is(0.0, EYE_DISTANCE, focal_px(&scene, size.1));
    let centre = size.0 as f32 / 2.0;
    for material in [true, false] {
        let seams = Seams { material, ..Seams::default() };
        let frame = render_seams(&gpu, &scene, size, ink, seams);
        let stats = frame.stats::<nostencil::stats::CartoonStats>().expect("stats");
        let image = &frame.output.image;
        image.save(dir.join(format!("material-seams-{material}.png"))).expect("save");
        let rows = (size.1 / 2 - (radius * 0.6) as u32)..(size.1 / 2 + (radius * 0.6) as u32);
        let crossed = rows
            .clone()
            .filter(|&y| (size.0 / 2 - 2..size.0 / 2 + 2).any(|x| image.get_pixel(x, y).0[..3] == blue))
            .count();
        let blue_columns: Vec<u32> =
            image.enumerate_pixels().filter(|(_, _, p)| p.0[..3] == blue).map(|(x, ..)| x).collect();
        if material {
            // The material border, and only it: within a line width of the centre column.
            assert_eq!(crossed, rows.len(), "material seam not drawn down the disc ({stats:?})");
            assert!(blue_columns.iter().all(|&x| (x as f32 + 0.5 - centre).abs() <= 3.0), "{stats:?}");
        } else {
            // The two halves weld into one closed sphere: no open edge, no boundary at all.
            assert_eq!((blue_columns.len(), stats.boundary_edges), (0, 0), "{stats:?}");
        }
    }
    common::assert_no_validation_messages(&gpu);
}
