//! The technique docs/adding-a-technique.md adds (`x-ray`: one folder, its `mod` line and its
//! registry line), built through the registry like every other and rendered: it draws where,
//! and as often as, CPU rays find a caster's front face behind the nearest surface.

use crate::common;

use common::ray_world::{Placed, RayWorld};
use glam::Vec3;
use nostencil::Scene;
use nostencil::{builtin_scene, render_scene, technique, RenderOptions};

const SIZE: u32 = 128;

/// The world ray through the point (x, y) of the frame, in pixels.
fn pixel_ray(scene: &Scene, x: f32, y: f32) -> (Vec3, Vec3) {
    let inverse = scene.camera.view_projection(1.0).inverse();
    let ndc = |p: f32| p / SIZE as f32 * 2.0 - 1.0;
    let near = inverse.project_point3(Vec3::new(ndc(x), ndc(y), 0.0));
    let far = inverse.project_point3(Vec3::new(ndc(x), ndc(y), 0.5));
    (near, (far - near).normalize())
}

/// By a CPU ray through the point (x, y): (how many caster front faces lie behind the nearest
/// surface, which object is nearest).
fn hidden_caster_at(scene: &Scene, world: &RayWorld, x: f32, y: f32) -> (usize, Option<usize>) {
    let (origin, dir) = pixel_ray(scene, x, y);
    let hits = world.every_hit(origin, dir);
    let Some(&(front, nearest)) = hits.iter().min_by(|a, b| a.1.total_cmp(&b.1)) else {
        return (0, None);
    };
    let radius = scene.camera.eye.length();
    let hidden = hits
        .iter()
        .filter(|(placed, distance)| {
            scene.objects[placed.object].casts_shadow
                && facing(placed, dir) < 0.0
                && *distance > nearest + 1e-4 * radius
        })
        .count();
    (hidden, Some(front.object))
}

/// The cosine between a triangle's front normal and the ray (negative: it faces the eye).
fn facing(placed: &Placed, dir: Vec3) -> f32 {
    let [a, b, c] = placed.corners;
    (b - a).cross(c - a).normalize_or_zero().dot(dir)
}

/// Whether a hidden caster's face on the ray through (x, y) is seen edge-on (within about 3
/// degrees), where the GPU may rasterise nothing or a sliver.
fn grazing_at(scene: &Scene, world: &RayWorld, x: f32, y: f32) -> bool {
    let (origin, dir) = pixel_ray(scene, x, y);
    world
        .every_hit(origin, dir)
        .iter()
        .any(|(placed, _)| scene.objects[placed.object].casts_shadow && facing(placed, dir).abs() < 0.05)
}

/// Whether the answer changes within half a pixel of the centre of pixel `i` (an edge of a
/// hidden face, which the pixel's neighbours may not show), or a hidden face is seen edge-on.
fn ambiguous(scene: &Scene, world: &RayWorld, i: usize) -> bool {
    let (x, y) = ((i as u32 % SIZE) as f32 + 0.5, (i as u32 / SIZE) as f32 + 0.5);
    let centre = hidden_caster_at(scene, world, x, y).0 > 0;
    grazing_at(scene, world, x, y)
        || [(-0.5, 0.0), (0.5, 0.0), (0.0, -0.5), (0.0, 0.5)]
            .into_iter()
            .any(|(dx, dy)| (hidden_caster_at(scene, world, x + dx, y + dy).0 > 0) != centre)
}

#[test]
fn x_ray_changes_exactly_the_pixels_where_a_caster_is_hidden() {
    let gpu = common::gpu();
    let scene = builtin_scene("default").expect("the default scene");
    let options = RenderOptions {
        width: SIZE,
        height: SIZE,
        technique: technique("x-ray").expect("x-ray is registered"),
        samples: 1,
        ..RenderOptions::default()
    };
    let xray = render_scene(&gpu, &scene, &options).expect("x-ray renders");
    let lit = render_scene(&gpu, &scene, &options.with_technique(technique("lit").expect("lit"))).expect("lit renders");
    let changed = common::differing_pixels(xray.output.image.as_raw(), lit.output.image.as_raw());
    let world = RayWorld::of(&scene);
    let truth: Vec<_> = (0..SIZE * SIZE)
        .map(|i| hidden_caster_at(&scene, &world, (i % SIZE) as f32 + 0.5, (i / SIZE) as f32 + 0.5))
        .collect();

    // A hidden face may blend to the bytes already there (the knot behind the knot, lit alike),
    // so a changed pixel proves a draw but an unchanged one proves nothing: the pass changes
    // no pixel the rays call clear, off an edge (where the nearest object or the answer changes
    // within half a pixel, or a hidden face is seen edge-on: the GPU samples the pixel centre
    // as the ray does, but depth and coverage round there).
    let hidden = |i: usize| truth[i].0 > 0;
    let at = |x: i64, y: i64| truth[(y.clamp(0, SIZE as i64 - 1) * SIZE as i64 + x.clamp(0, SIZE as i64 - 1)) as usize];
    let on_edge = |i: usize| {
        let (x, y) = ((i as u32 % SIZE) as i64, (i as u32 / SIZE) as i64);
        let centre = at(x, y);
        (-1..=1)
            .any(|dy| (-1..=1).any(|dx| (at(x + dx, y + dy).0 > 0, at(x + dx, y + dy).1) != (centre.0 > 0, centre.1)))
    };
    let stray: Vec<usize> = (0..truth.len())
        .filter(|&i| changed[i] && !hidden(i) && !on_edge(i) && !ambiguous(&scene, &world, i))
        .collect();
    assert!(
        stray.is_empty(),
        "{} pixels changed where the rays find no hidden caster, e.g. {:?}",
        stray.len(),
        stray.iter().take(5).map(|&i| (i as u32 % SIZE, i as u32 / SIZE)).collect::<Vec<_>>()
    );
    let expected_pixels = (0..truth.len()).filter(|&i| hidden(i)).count();
    let changed_inside = (0..truth.len()).filter(|&i| changed[i] && hidden(i)).count();
    assert!(
        expected_pixels > 100,
        "the default scene hides only {expected_pixels} caster pixels: too few to prove much"
    );
    assert!(
        changed_inside * 2 > expected_pixels,
        "only {changed_inside} of {expected_pixels} pixels with a hidden caster changed"
    );

    // How often: the pass's samples passed (one sample a pixel) count every hidden front face
    // the depth test let through, which the rays count layer by layer.
    let layers: usize = truth.iter().map(|t| t.0).sum();
    let pass = xray.output.counters.passes.iter().find(|p| p.name == "x-ray").expect("the x-ray pass is measured");
    let ratio = pass.samples_passed as f64 / layers as f64;
    assert!((0.97..=1.03).contains(&ratio), "{} samples passed for {layers} hidden layers", pass.samples_passed);

    // Nothing is drawn where nothing hides a caster, so the background is untouched and the
    // x-ray pass is the only pass that differs from lit.
    let names: Vec<&str> = xray.output.counters.passes.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["scene", "x-ray"]);
    common::assert_no_validation_messages(&gpu);
}
