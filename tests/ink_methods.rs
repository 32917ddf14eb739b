//! The seed-002 ink methods measured against what they must draw, computed on the CPU: the
//! alpha test's ring on a sphere is where N.V < the reference value.

mod common;

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use image::RgbaImage;
use nostencil::frame::StencilMode;
use nostencil::gpu::Gpu;
use nostencil::mesh::{shapes, MeshData};
use nostencil::scene::{Camera, Light, Scene};
use nostencil::technique::ink::{SILHOUETTE, TOON};
use nostencil::technique::{render_scene, CartoonOptions, RenderOptions, SilhouetteMethod, Technique};

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
    technique: &'static dyn Technique,
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
        for technique in [&SILHOUETTE as &'static dyn Technique, &TOON] {
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
