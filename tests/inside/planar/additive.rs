//! Several lights: the additive loop (docs/design/planar-shadows.md, "Several lights").

use super::*;

#[test]
fn additive_planar_equals_the_reference_on_every_scene_at_1x_and_4x() {
    let gpu = common::gpu();
    let size = (96, 72);
    let mut compared = 0;
    for &(name, _) in nostencil::BUILTIN_SCENES {
        let scene = builtin_scene_at(name, 0.5).expect("scene");
        if planar::receiver_plane(&scene, None).is_err() {
            continue; // slope: a tilted plane is given by hand (tested above)
        }
        for samples in [1, 4] {
            let emulated = additive(&gpu, &scene, size, StencilMode::Emulated, samples);
            let reference = additive(&gpu, &scene, size, StencilMode::Reference, samples);
            let differing = rgb_differences(&emulated.output.image, &reference.output.image);
            assert_eq!(differing, 0, "{name} at {samples}x: {differing} pixels differ from Ogre's stencil loop");
            let flags = |f: &TechniqueFrame| {
                f.output.counters.passes.iter().filter(|p| p.name.ends_with("planar shadow")).count()
            };
            assert_eq!(flags(&emulated), flags(&reference), "{name}: the same flags drawn");
            compared += 1;
        }
    }
    assert!(compared >= 20, "only {compared} scene x sample cases have a ground");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn each_lights_planar_shadow_removes_only_that_light() {
    let gpu = common::gpu();
    let scene = builtin_scene_at("lights", 0.0).expect("lights");
    let plane = planar::receiver_plane(&scene, None).expect("ground");
    let receivers = receiver_mask(&render(&gpu, &scene, StencilMode::Emulated, false).output.image);
    let frame = additive(&gpu, &scene, SIZE, StencilMode::Emulated, 1);
    assert!(frame.warnings.is_empty(), "{:?}", frame.warnings);
    // Where the CPU projects each light's casters.
    let masks: Vec<Vec<bool>> = scene
        .lights
        .iter()
        .map(|light| {
            let caster = |i: usize| !plane.receivers[i];
            let project = |p: Vec3| project_onto_plane(p, &light.geometry(), plane.height);
            cpu_shadow_mask(&scene, &triangles_projected_by(&scene, caster, project))
        })
        .collect();
    // Receiver pixels away from every shadow's edge, by the set of lights whose shadow covers them.
    let mut by_shadows: std::collections::BTreeMap<u32, Vec<usize>> = Default::default();
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let i = (y * SIZE.0 + x) as usize;
            if interior(&receivers, x, y) && receivers[i] && masks.iter().all(|m| interior(m, x, y)) {
                let shadows = masks.iter().enumerate().filter(|(_, m)| m[i]).fold(0, |bits, (l, _)| bits | 1 << l);
                by_shadows.entry(shadows).or_default().push(i);
            }
        }
    }
    // Each region equals the lit frame without the lights that shadow it: a shadow removes its
    // own light's term and nothing else, once however many casters overlap there.
    let mut worst = 0;
    for (&shadows, pixels) in &by_shadows {
        let mut without = scene.clone();
        for (l, light) in without.lights.iter_mut().enumerate() {
            if shadows & 1 << l != 0 {
                light.intensity = 0.0;
            }
        }
        let options =
            RenderOptions { width: SIZE.0, height: SIZE.1, technique: technique("lit"), ..Default::default() };
        let lit = render_scene(&gpu, &without, &options).expect("lit").output.image;
        for &i in pixels {
            let (p, q) = (&frame.output.image.as_raw()[i * 4..i * 4 + 3], &lit.as_raw()[i * 4..i * 4 + 3]);
            let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0);
            worst = worst.max(d);
            assert!(d <= 2, "pixel {i} under shadows {shadows:03b}: {p:?}, lit without them {q:?}");
        }
    }
    let count = |bits: u32| by_shadows.get(&bits).map_or(0, Vec::len);
    for l in 0..scene.lights.len() {
        assert!(count(1 << l) >= 15, "light {l}'s shadow alone covers {} pixels: {by_shadows:?}", count(1 << l));
    }
    assert!(
        by_shadows.keys().any(|bits| bits.count_ones() >= 2 && count(*bits) >= 5),
        "no two shadows overlap: {:?}",
        by_shadows.iter().map(|(b, p)| (b, p.len())).collect::<Vec<_>>()
    );
    eprintln!(
        "regions: {:?}, worst {worst}/255",
        by_shadows.iter().map(|(b, p)| (format!("{b:03b}"), p.len())).collect::<Vec<_>>()
    );
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn a_light_that_cannot_reach_the_plane_is_named_and_still_shades() {
    let gpu = common::gpu();
    let mut scene = builtin_scene_at("default", 0.0).expect("default");
    let mut grazing =
        nostencil::scene::lights::parse_light_spec("directional:name=grazing:dir=1,0,0:intensity=0.5").expect("spec");
    grazing.colour = Vec3::new(0.2, 0.6, 1.0);
    scene.lights.push(grazing);
    let emulated = additive(&gpu, &scene, SIZE, StencilMode::Emulated, 1);
    let reference = additive(&gpu, &scene, SIZE, StencilMode::Reference, 1);
    assert!(
        emulated.warnings.iter().any(|w| w.contains("'grazing' casts no shadow") && w.contains("parallel")),
        "{:?}",
        emulated.warnings
    );
    assert_eq!(rgb_differences(&emulated.output.image, &reference.output.image), 0);
    let without = additive(&gpu, &builtin_scene_at("default", 0.0).expect("default"), SIZE, StencilMode::Emulated, 1);
    let lit_by_it = rgb_differences(&emulated.output.image, &without.output.image);
    assert!(lit_by_it > 500, "the grazing light shades only {lit_by_it} pixels");
    // The seed's mode has one shadow, from the primary light: it still refuses a parallel one.
    let mut parallel = builtin_scene_at("default", 0.0).expect("default");
    parallel.lights[0].direction = Vec3::X;
    let err = render_with(&gpu, &parallel, technique("planar"), SIZE, StencilMode::Emulated, PlanarOptions::default())
        .err()
        .expect("modulate refuses a light parallel to the plane");
    assert!(err.to_string().contains("parallel"), "{err}");
    common::assert_no_validation_messages(&gpu);
}
