//! Several lights, and shadows that remove only their own light (issue 27): the additive loop
//! of shadow volumes measured against witnesses it does not share code with: the shadow map
//! (which sees only real occlusion), CPU rays toward each light, and the KHR_lights_punctual
//! formulas evaluated on the CPU.

use crate::common;

use common::ray_world::RayWorld;
use glam::{Mat4, Vec3};
use nostencil::scene::lights::parse_light_spec;
use nostencil::ShadowMode;
use nostencil::{builtin_scene, render_scene, technique, RenderOptions, StencilMode};
use nostencil::{Camera, Light, Scene, SceneLight};

/// Renders `scene` with `technique` at `size`, one sample.
fn render(scene: &Scene, name: &str, size: (u32, u32), mode: ShadowMode) -> image::RgbaImage {
    let gpu = common::gpu();
    let mut options = RenderOptions {
        width: size.0,
        height: size.1,
        technique: technique(name).expect("technique"),
        ..RenderOptions::default()
    };
    options.shadow_mode = mode;
    let frame = render_scene(&gpu, scene, &options).unwrap_or_else(|e| panic!("{name} renders: {e}"));
    common::assert_no_validation_messages(&gpu);
    frame.output.image
}

/// Pixels darker than `lit` by more than 8 levels summed over RGB.
fn darkened(lit: &image::RgbaImage, frame: &image::RgbaImage) -> Vec<bool> {
    lit.pixels()
        .zip(frame.pixels())
        .map(|(l, f)| (0..3).map(|c| i32::from(l[c]) - i32::from(f[c])).sum::<i32>() > 8)
        .collect()
}

fn count(mask: &[bool]) -> usize {
    mask.iter().filter(|&&m| m).count()
}

fn intersection_over_union(a: &[bool], b: &[bool]) -> f64 {
    let both = a.iter().zip(b).filter(|(x, y)| **x && **y).count();
    let either = a.iter().zip(b).filter(|(x, y)| **x || **y).count();
    both as f64 / either.max(1) as f64
}

/// The world ray through the point (x, y) of a `size` frame, in pixels.
fn pixel_ray(camera: &Camera, (x, y): (f32, f32), size: (u32, u32)) -> (Vec3, Vec3) {
    let inverse = camera.view_projection(size.0 as f32 / size.1 as f32).inverse();
    let ndc = |p: f32, side: u32| p / side as f32 * 2.0 - 1.0;
    let near = inverse.project_point3(Vec3::new(ndc(x, size.0), ndc(y, size.1), 0.0));
    let far = inverse.project_point3(Vec3::new(ndc(x, size.0), ndc(y, size.1), 0.5));
    (near, (far - near).normalize())
}

/// The measure: on the default scene at 320x240, the pixels each shadow mode darkens
/// below `lit` against those the shadow map darkens. Modulate darkens faces the light already
/// leaves dark and the terminator bands a second time; additive removes only the light, so it
/// darkens (almost) only where the map sees occlusion.
#[test]
fn additive_darkens_where_the_shadow_map_does_and_modulate_does_not() {
    const SIZE: (u32, u32) = (320, 240);
    let scene = builtin_scene("default").expect("scene");
    let lit = render(&scene, "lit", SIZE, ShadowMode::Additive);
    let map = darkened(&lit, &render(&scene, "shadow-map", SIZE, ShadowMode::Additive));
    let modulate = darkened(&lit, &render(&scene, "shadow-volume", SIZE, ShadowMode::Modulate));
    let additive = darkened(&lit, &render(&scene, "shadow-volume", SIZE, ShadowMode::Additive));
    let beyond = |mask: &[bool]| mask.iter().zip(&map).filter(|(m, in_map)| **m && !**in_map).count();
    let (modulate_extra, additive_extra) = (beyond(&modulate), beyond(&additive));
    let iou = intersection_over_union(&additive, &map);
    println!(
        "darkened: map {}, modulate {} ({} beyond the map), additive {} ({} beyond the map), IoU(additive, map) {iou:.3}",
        count(&map),
        count(&modulate),
        modulate_extra,
        count(&additive),
        additive_extra
    );
    assert!(
        modulate_extra >= 1000,
        "modulate darkens only {modulate_extra} pixels the map does not: the measure is void"
    );
    assert!(
        additive_extra * 5 <= modulate_extra,
        "additive darkens {additive_extra} pixels the map does not, modulate {modulate_extra}: not cut by 80%"
    );
    assert!(iou >= 0.85, "IoU of additive's and the map's darkened pixels: {iou:.3}");
}

/// A caster's own pixel is darker than `lit` only where a CPU ray from its surface toward the
/// light finds something in the way (self-shadowing included), never where the light already
/// leaves it dark: the second half of "no double darkening", against rays.
#[test]
fn a_surface_is_darkened_only_where_a_ray_to_the_light_is_blocked() {
    const SIZE: (u32, u32) = (256, 192);
    let scene = builtin_scene("default").expect("scene");
    let lit = render(&scene, "lit", SIZE, ShadowMode::Additive);
    let additive = darkened(&lit, &render(&scene, "shadow-volume", SIZE, ShadowMode::Additive));
    let world = RayWorld::of(&scene);
    let Light::Directional { direction } = scene.light() else { panic!("the default scene's sun") };
    let toward_light = -direction.normalize();
    let radius = scene.camera.eye.length();
    // Whether the surface seen at a point of the pixel is in the light's shadow (by a ray).
    let blocked_at = |x: f32, y: f32| -> Option<bool> {
        let (near, dir) = pixel_ray(&scene.camera, (x, y), SIZE);
        let hit = world.first_hit(near, dir)?;
        let point = near + dir * hit.distance;
        Some(world.occluder(point + toward_light * 1e-3 * radius, toward_light).is_some())
    };
    let (mut checked, mut wrong) = (0, Vec::new());
    for (i, &dark) in additive.iter().enumerate() {
        let (x, y) = ((i as u32 % SIZE.0) as f32 + 0.5, (i as u32 / SIZE.0) as f32 + 0.5);
        let Some(centre) = blocked_at(x, y) else { continue };
        // Pixels on a shadow's edge (or an object's) may go either way.
        let edge = [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)]
            .into_iter()
            .any(|(dx, dy)| blocked_at(x + dx, y + dy) != Some(centre));
        if edge {
            continue;
        }
        checked += 1;
        if dark && !centre {
            wrong.push((x as u32, y as u32));
        }
    }
    println!("{checked} pixels checked, {} darkened with an open ray to the light", wrong.len());
    assert!(checked > SIZE.0 as usize * SIZE.1 as usize / 2, "only {checked} pixels away from edges");
    assert!(
        wrong.len() * 1000 <= checked,
        "{} pixels darkened though the ray to the light is open (more than 0.1%), e.g. {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(8)]
    );
}

/// The KHR_lights_punctual contribution of `light` at `point` on a surface of normal `n`
/// (`shaders/lights.glsl`, written again).
fn contribution(light: &SceneLight, point: Vec3, n: Vec3) -> Vec3 {
    let to_light = light.position - point;
    let d = to_light.length();
    let l = to_light / d;
    let range = light.range.map_or(f32::INFINITY, |r| r);
    let window = (1.0 - (d / range).powi(4)).clamp(0.0, 1.0);
    let (scale, offset) = light.cone_scale_offset();
    let cone = (light.direction.normalize().dot(-l) * scale + offset).clamp(0.0, 1.0);
    light.radiance() * n.dot(l).max(0.0) * window * cone * cone / (d * d)
}

/// A blue spot with a hard edge (inner cone 0.6 degrees inside the outer) and a red point lamp
/// whose range ends on the ground, over a bare ground: each channel holds one light.
fn cone_and_range_scene() -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 13.0, 3.0), Vec3::ZERO);
    let mut scene = Scene::empty("cone-and-range", camera, Light::Directional { direction: Vec3::NEG_Y });
    let ground = scene.add_mesh("ground", nostencil::mesh::shapes::quad(Vec3::ZERO, Vec3::Y, glam::Vec2::splat(30.0)));
    scene.add_object("ground", ground, Mat4::IDENTITY, Vec3::splat(0.8), false);
    scene.lights = vec![
        parse_light_spec("spot:name=spot:at=-2.5,4,0:dir=0,-1,0:outer=30:inner=29.4:colour=0,0,1:intensity=40")
            .expect("spec"),
        parse_light_spec("point:name=lamp:at=3,1,0:range=3:colour=1,0,0:intensity=4").expect("spec"),
    ];
    scene
}

/// The spot's cone edge on the ground lies within 1 px of the CPU's cone: every pixel whose
/// neighbours all lie inside the inner cone is lit, and every lit pixel has a neighbour inside
/// the outer cone. The lamp's light ends at its range: nothing is added beyond it, and inside it
/// each pixel is ambient plus the KHR falloff computed on the CPU, within 2/255 (as are the
/// spot's pixels).
#[test]
fn a_spots_cone_edge_and_a_lamps_range_fall_where_the_spec_says() {
    const SIZE: (u32, u32) = (256, 256);
    let scene = cone_and_range_scene();
    let frame = render(&scene, "lit", SIZE, ShadowMode::Additive);
    let [spot, lamp] = [&scene.lights[0], &scene.lights[1]];
    let LightKindAngles { inner, outer } = angles(spot);
    let ground_at = |x: f32, y: f32| {
        let (near, dir) = pixel_ray(&scene.camera, (x, y), SIZE);
        (dir.y < 0.0).then(|| near + dir * (-near.y / dir.y))
    };
    let axis_cos = |p: Vec3| (p - spot.position).normalize().dot(spot.direction.normalize());
    let (w, h) = (SIZE.0 as i32, SIZE.1 as i32);
    let points: Vec<Option<Vec3>> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| ground_at(x as f32 + 0.5, y as f32 + 0.5))
        .collect();
    let neighbours = |x: i32, y: i32| {
        (-1..=1)
            .flat_map(move |dy| (-1..=1).map(move |dx| (x + dx, y + dy)))
            .filter(|&(x, y)| x >= 0 && y >= 0 && x < w && y < h)
    };
    let ambient = common::srgb8(Vec3::splat(0.8 * scene.ambient));
    let (mut inside, mut edge_pixels, mut beyond, mut in_range, mut worst) = (0, 0, 0, 0, 0u8);
    for y in 0..h {
        for x in 0..w {
            let Some(point) = points[(y * w + x) as usize] else { continue };
            let pixel = frame.get_pixel(x as u32, y as u32);
            let lit = pixel[2] > ambient[2] + 2;
            let all_inner =
                neighbours(x, y).all(|(x, y)| points[(y * w + x) as usize].is_some_and(|p| axis_cos(p) >= inner.cos()));
            let any_outer =
                neighbours(x, y).any(|(x, y)| points[(y * w + x) as usize].is_some_and(|p| axis_cos(p) > outer.cos()));
            assert!(!all_inner || lit, "pixel ({x}, {y}) lies inside the inner cone, yet the spot does not light it");
            assert!(!lit || any_outer, "pixel ({x}, {y}) is lit more than 1 px outside the outer cone");
            inside += usize::from(all_inner);
            edge_pixels += usize::from(lit && !all_inner);
            // The lamp: nothing beyond its range; the spec's falloff inside it.
            let d = point.distance(lamp.position);
            if d > lamp.range.unwrap_or(f32::INFINITY) {
                beyond += 1;
                assert_eq!(
                    pixel[0], ambient[0],
                    "pixel ({x}, {y}) at {d:.3} m lies beyond the lamp's range, yet is lit"
                );
            } else {
                in_range += 1;
            }
            let spot_settled = all_inner || !any_outer;
            if spot_settled {
                let expected = common::srgb8(
                    Vec3::splat(0.8)
                        * (Vec3::splat(scene.ambient)
                            + contribution(spot, point, Vec3::Y)
                            + contribution(lamp, point, Vec3::Y)),
                );
                let off = (0..3).map(|c| pixel[c].abs_diff(expected[c])).max().unwrap_or(0);
                worst = worst.max(off);
                assert!(off <= 2, "pixel ({x}, {y}) at {point}: {:?}, the CPU says {expected:?}", &pixel.0[..3]);
            }
        }
    }
    println!("spot: {inside} pixels inside the inner cone, {edge_pixels} lit on the edge band; lamp: {in_range} pixels in range, {beyond} beyond; worst {worst}/255");
    assert!(inside > 2_000 && in_range > 2_000 && beyond > 10_000, "{inside} {in_range} {beyond}");
}

struct LightKindAngles {
    inner: f32,
    outer: f32,
}

fn angles(light: &SceneLight) -> LightKindAngles {
    match light.kind {
        nostencil::scene::model::LightKind::Spot { inner_cone_angle, outer_cone_angle } => {
            LightKindAngles { inner: inner_cone_angle, outer: outer_cone_angle }
        }
        _ => panic!("'{}' is not a spot", light.name),
    }
}

/// Two coloured point lights (red and green) and a box on the ground: the ground falls into
/// regions lit by both, by one, by the other and by none, as CPU rays to each light decide.
fn two_lights_scene() -> Scene {
    let camera = Camera::look_at(Vec3::new(0.0, 6.0, 6.5), Vec3::new(0.0, 0.0, 0.5));
    let mut scene = Scene::empty("two-lights", camera, Light::Directional { direction: Vec3::NEG_Y });
    let ground = scene.add_mesh("ground", nostencil::mesh::shapes::quad(Vec3::ZERO, Vec3::Y, glam::Vec2::splat(16.0)));
    scene.add_object("ground", ground, Mat4::IDENTITY, Vec3::splat(0.8), false);
    let cube = scene.add_mesh("box", nostencil::mesh::shapes::cube(1.0));
    scene.add_object("box", cube, Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0)), Vec3::splat(0.8), true);
    scene.lights = vec![
        parse_light_spec("point:name=red:at=-0.9,2.4,-1.3:colour=1,0,0:intensity=7:range=12").expect("spec"),
        parse_light_spec("point:name=green:at=0.9,2.6,-1.1:colour=0,1,0:intensity=8:range=12").expect("spec"),
    ];
    scene
}

/// Each ground pixel equals ambient plus the contributions of the lights whose ray reaches it,
/// computed on the CPU, within 2/255; each light's shadow (read from its own channel) matches
/// the rays' outline with IoU >= 0.99. Emulated and reference frames are equal first.
#[test]
fn two_point_lights_and_a_box_match_the_cpu() {
    const SIZE: (u32, u32) = (256, 192);
    let scene = two_lights_scene();
    let gpu = common::gpu();
    let options = RenderOptions {
        width: SIZE.0,
        height: SIZE.1,
        technique: technique("shadow-volume").expect("technique"),
        ..RenderOptions::default()
    };
    let frame = render_scene(&gpu, &scene, &options).expect("renders").output.image;
    let reference = render_scene(&gpu, &scene, &RenderOptions { stencil: StencilMode::Reference, ..options.clone() })
        .expect("reference renders")
        .output
        .image;
    common::assert_no_validation_messages(&gpu);
    assert_eq!(
        common::differing_pixels(frame.as_raw(), reference.as_raw()).iter().filter(|&&d| d).count(),
        0,
        "emulated and reference differ"
    );

    let world = RayWorld::of(&scene);
    let albedo = Vec3::splat(0.8);
    // (ground point, lit by each light) through a point of the frame, None off the ground.
    let classify = |x: f32, y: f32| -> Option<(Vec3, [bool; 2])> {
        let (near, dir) = pixel_ray(&scene.camera, (x, y), SIZE);
        let hit = world.first_hit(near, dir)?;
        (scene.objects[hit.object].name == "ground").then_some(())?;
        let point = near + dir * hit.distance;
        let lit = [0, 1].map(|i| {
            let to_light = scene.lights[i].position - point;
            let blocker = world.first_hit(point + Vec3::Y * 1e-4, to_light.normalize());
            blocker.is_none_or(|b| b.distance > to_light.length())
        });
        Some((point, lit))
    };
    let (mut regions, mut worst, mut checked) = ([0usize; 4], 0u8, 0usize);
    let mut masks = [vec![false; frame.len() / 4], vec![false; frame.len() / 4]];
    let mut truths = masks.clone();
    let mut ground = vec![false; frame.len() / 4];
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
            let Some((point, lit)) = classify(cx, cy) else { continue };
            let i = (y * SIZE.0 + x) as usize;
            ground[i] = true;
            let pixel = frame.get_pixel(x, y);
            let mut expected = albedo * scene.ambient;
            for (light, _) in scene.lights.iter().zip(lit).filter(|(_, lit)| *lit) {
                expected += albedo * contribution(light, point, Vec3::Y);
            }
            let expected = common::srgb8(expected);
            // Each light's shadow, read from its own channel: shadowed where the channel is
            // nearer the unlit value than the lit one.
            for (c, light) in scene.lights.iter().enumerate() {
                let unlit = albedo * scene.ambient;
                let full = unlit + albedo * contribution(light, point, Vec3::Y);
                let (dark, bright) = (common::srgb8(unlit)[c] as f32, common::srgb8(full)[c] as f32);
                masks[c][i] = bright - dark > 6.0 && (pixel[c] as f32) < (dark + bright) / 2.0;
                truths[c][i] = bright - dark > 6.0 && !lit[c];
            }
            let edge = [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)]
                .into_iter()
                .any(|(dx, dy)| classify(cx + dx, cy + dy).map(|(_, l)| l) != Some(lit));
            if edge {
                continue;
            }
            checked += 1;
            regions[usize::from(lit[0]) + 2 * usize::from(lit[1])] += 1;
            let off = (0..3).map(|c| pixel[c].abs_diff(expected[c])).max().unwrap_or(0);
            worst = worst.max(off);
            assert!(off <= 2, "pixel ({x}, {y}), lit by {lit:?}: {:?}, the CPU says {expected:?}", &pixel.0[..3]);
        }
    }
    println!("{checked} ground pixels checked; regions (none, red, green, both): {regions:?}; worst {worst}/255");
    assert!(regions.iter().all(|&n| n > 100), "each region needs pixels: {regions:?}");
    for (c, light) in scene.lights.iter().enumerate() {
        let (mask, truth): (Vec<bool>, Vec<bool>) =
            masks[c].iter().zip(&truths[c]).zip(&ground).map(|((m, t), g)| (*m && *g, *t && *g)).unzip();
        let iou = intersection_over_union(&mask, &truth);
        println!("'{}': shadow of {} pixels, IoU against the rays {iou:.4}", light.name, count(&truth));
        assert!(count(&truth) > 200, "'{}' casts too small a shadow to measure", light.name);
        assert!(iou >= 0.99, "'{}': IoU {iou:.4}", light.name);
    }
}

/// A glTF file with a box and four KHR_lights_punctual lights on nodes: a sun, a red point
/// lamp with a range, a blue spot on a node whose translation is animated over 1 s (from
/// x = 1.5 to x = -0.5), and a dim green bulb, a point light without a range.
fn three_lights_gltf() -> Vec<u8> {
    use base64::Engine as _;
    let cube = nostencil::mesh::shapes::cube(1.0);
    let mut bin: Vec<u8> = Vec::new();
    let floats = |bin: &mut Vec<u8>, values: &[f32]| values.iter().for_each(|v| bin.extend(v.to_le_bytes()));
    floats(&mut bin, &cube.positions.iter().flat_map(|p| p.to_array()).collect::<Vec<f32>>());
    let normals_at = bin.len();
    floats(&mut bin, &cube.normals.iter().flat_map(|n| n.to_array()).collect::<Vec<f32>>());
    let indices_at = bin.len();
    cube.indices.iter().for_each(|i| bin.extend(i.to_le_bytes()));
    let times_at = bin.len();
    floats(&mut bin, &[0.0, 1.0]);
    let moves_at = bin.len();
    floats(&mut bin, &[1.5, 3.0, 0.5, -0.5, 3.0, 0.5]);
    let n = cube.positions.len();
    let view =
        |offset: usize, length: usize| serde_json::json!({ "buffer": 0, "byteOffset": offset, "byteLength": length });
    let (lo, hi) = (Vec3::splat(-0.5), Vec3::splat(0.5));
    let json = serde_json::json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": { "KHR_lights_punctual": { "lights": [
            { "name": "sun", "type": "directional", "color": [1.0, 0.9, 0.8], "intensity": 0.5 },
            { "name": "lamp", "type": "point", "color": [1.0, 0.2, 0.1], "intensity": 2.0, "range": 6.0 },
            { "name": "spot", "type": "spot", "color": [0.2, 0.4, 1.0], "intensity": 12.0, "range": 9.0,
              "spot": { "innerConeAngle": 0.3, "outerConeAngle": 0.5 } },
            { "name": "bulb", "type": "point", "color": [0.3, 1.0, 0.4], "intensity": 1.5 }
        ] } },
        "scene": 0,
        "scenes": [{ "nodes": [0, 1, 2, 3, 4] }],
        "nodes": [
            { "name": "box", "mesh": 0, "translation": [0.0, 0.5, 0.0] },
            { "name": "sun node", "rotation": [-0.5, 0.0, 0.0, 0.8660254], "extensions": { "KHR_lights_punctual": { "light": 0 } } },
            { "name": "lamp node", "translation": [-1.5, 2.0, 1.0], "extensions": { "KHR_lights_punctual": { "light": 1 } } },
            { "name": "spot node", "translation": [1.5, 3.0, 0.5], "rotation": [-0.70710677, 0.0, 0.0, 0.70710677],
              "extensions": { "KHR_lights_punctual": { "light": 2 } } },
            { "name": "bulb node", "translation": [1.5, 2.5, -1.5], "extensions": { "KHR_lights_punctual": { "light": 3 } } }
        ],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0, "NORMAL": 1 }, "indices": 2 }] }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3", "min": lo.to_array(), "max": hi.to_array() },
            { "bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3" },
            { "bufferView": 2, "componentType": 5125, "count": cube.indices.len(), "type": "SCALAR" },
            { "bufferView": 3, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [1.0] },
            { "bufferView": 4, "componentType": 5126, "count": 2, "type": "VEC3" }
        ],
        "bufferViews": [
            view(0, normals_at), view(normals_at, indices_at - normals_at), view(indices_at, times_at - indices_at),
            view(times_at, moves_at - times_at), view(moves_at, bin.len() - moves_at)
        ],
        "animations": [{
            "samplers": [{ "input": 3, "output": 4, "interpolation": "LINEAR" }],
            "channels": [{ "sampler": 0, "target": { "node": 3, "path": "translation" } }]
        }],
        "buffers": [{
            "byteLength": bin.len(),
            "uri": format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bin))
        }]
    });
    serde_json::to_vec(&json).expect("JSON")
}

/// KHR_lights_punctual lights on their nodes become the scene's lights, named, coloured and
/// placed by their nodes; an animated node carries its light along; and the frame shows each
/// light's colour where it reaches, emulated equal to the reference.
#[test]
fn a_gltf_files_lights_light_the_frame_and_follow_their_nodes() {
    use nostencil::scene::{model::LightKind, scene_and_warnings_from_gltf_slice};
    let bytes = three_lights_gltf();
    let path = std::path::Path::new("three-lights.gltf");
    let (scene, warnings) = scene_and_warnings_from_gltf_slice(&bytes, path, 0.0).expect("the file loads");
    assert!(warnings.is_empty(), "{warnings:?}");
    let names: Vec<&str> = scene.lights.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names, ["sun", "lamp", "spot", "bulb"]);
    let bulb = &scene.lights[3];
    assert_eq!((bulb.kind, bulb.range), (LightKind::Point, None), "a point light without a range");
    assert!(bulb.position.distance(Vec3::new(1.5, 2.5, -1.5)) < 1e-5);
    let (sun, lamp, spot) = (&scene.lights[0], &scene.lights[1], &scene.lights[2]);
    assert_eq!(sun.kind, LightKind::Directional);
    assert!(sun.direction.distance(Vec3::new(0.0, -0.8660254, -0.5)) < 1e-4, "{}", sun.direction);
    assert_eq!((lamp.kind, lamp.range, lamp.colour), (LightKind::Point, Some(6.0), Vec3::new(1.0, 0.2, 0.1)));
    assert!(lamp.position.distance(Vec3::new(-1.5, 2.0, 1.0)) < 1e-5);
    assert_eq!(spot.kind, LightKind::Spot { inner_cone_angle: 0.3, outer_cone_angle: 0.5 });
    assert!(spot.direction.distance(Vec3::NEG_Y) < 1e-5, "{}", spot.direction);
    assert!(spot.position.distance(Vec3::new(1.5, 3.0, 0.5)) < 1e-5);
    // The spot rides on its animated node: half-way through, half-way along.
    let (half, _) = scene_and_warnings_from_gltf_slice(&bytes, path, 0.5).expect("the file loads");
    assert!(half.lights[2].position.distance(Vec3::new(0.5, 3.0, 0.5)) < 1e-4, "{}", half.lights[2].position);
    let mut posed = scene.clone();
    posed.pose_at(0.5).expect("pose");
    assert!(posed.lights[2].position.distance(half.lights[2].position) < 1e-6);

    // The lamp's red where it reaches: the ground under it, with and without the lamp.
    const SIZE: (u32, u32) = (128, 96);
    let with = render(&scene, "shadow-volume", SIZE, ShadowMode::Additive);
    let mut without_lamp = scene.clone();
    without_lamp.lights.remove(1);
    let without = render(&without_lamp, "shadow-volume", SIZE, ShadowMode::Additive);
    let ground = scene.object("ground").expect("the loader's ground plane");
    // Between the box and the lamp's foot, a metre from each: in the frame the loader fits.
    let near_lamp = Vec3::new(-0.9, ground.transform.w_axis.y, 0.6);
    let clip = scene.camera.view_projection(SIZE.0 as f32 / SIZE.1 as f32) * near_lamp.extend(1.0);
    let (x, y) = ((clip.x / clip.w * 0.5 + 0.5) * SIZE.0 as f32, (clip.y / clip.w * 0.5 + 0.5) * SIZE.1 as f32);
    assert!((0.0..SIZE.0 as f32).contains(&x) && (0.0..SIZE.1 as f32).contains(&y), "({x}, {y}) is off the frame");
    let (a, b) = (with.get_pixel(x as u32, y as u32), without.get_pixel(x as u32, y as u32));
    // What the lamp adds, in linear light: red, five times its green (its colour 1, 0.2, 0.1).
    let added = |c: usize| common::srgb_decode(a[c]) - common::srgb_decode(b[c]);
    assert!(added(0) > 0.1 && added(0) > 3.0 * added(1), "near the red lamp: {a:?} with it, {b:?} without");
    let gpu = common::gpu();
    let options = RenderOptions {
        width: SIZE.0,
        height: SIZE.1,
        technique: technique("shadow-volume").expect("technique"),
        ..RenderOptions::default()
    };
    let reference = render_scene(&gpu, &scene, &RenderOptions { stencil: StencilMode::Reference, ..options.clone() })
        .expect("reference")
        .output
        .image;
    common::assert_no_validation_messages(&gpu);
    let differing = common::differing_pixels(with.as_raw(), reference.as_raw()).iter().filter(|&&d| d).count();
    assert_eq!(differing, 0, "emulated and reference differ in {differing} pixels");
    // Planar shadows, one per light, against their reference on the same file.
    let planar = RenderOptions { technique: technique("planar").expect("technique"), ..options };
    let emulated = render_scene(&gpu, &scene, &planar).expect("planar").output.image;
    let reference = render_scene(&gpu, &scene, &RenderOptions { stencil: StencilMode::Reference, ..planar.clone() })
        .expect("planar reference")
        .output
        .image;
    common::assert_no_validation_messages(&gpu);
    // RGB: alpha is each path's working state (the emulated flags, the reference's colour).
    let differing = emulated.pixels().zip(reference.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count();
    assert_eq!(differing, 0, "planar: emulated and reference differ in {differing} pixels");
}

/// The command line's lights: `--light` adds to the scene's, `--replace-lights` puts the given
/// ones in their place, `--light-scale` multiplies every light's intensity (not ambient or
/// emissive); a bad value is named with its flag.
#[test]
fn command_line_lights_add_replace_and_scale() {
    let dir = common::scratch_dir("command-line-lights");
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let args =
            [&["render", "--technique", "lit", "--size", "96x72", "--out", out.to_str().unwrap()], extra].concat();
        common::run_ok(&args);
        common::read_png(&out)
    };
    let base = render("base.png", &[]);
    let red = render("red.png", &["--light", "point:at=0,3,0:colour=1,0,0:intensity=30"]);
    let brighter = base.pixels().zip(red.pixels()).filter(|(b, r)| r[0] > b[0]).count();
    assert!(brighter > 1_000, "a red point light brightened only {brighter} pixels' red");
    assert!(
        base.pixels().zip(red.pixels()).all(|(b, r)| r[0] >= b[0] && r[1] == b[1] && r[2] == b[2]),
        "a red light added changed green or blue, or darkened red"
    );
    let replaced = render("replaced.png", &["--replace-lights", "--light", "directional:dir=0,-1,0:intensity=0"]);
    let unlit = render("unlit.png", &["--light-scale", "0"]);
    assert_eq!(replaced, unlit, "no light left (replaced by a dark one) differs from every light scaled to 0");
    assert!(base.pixels().zip(unlit.pixels()).all(|(b, u)| (0..3).all(|c| u[c] <= b[c])), "scale 0 brightened");
    let doubled = render("doubled.png", &["--light-scale", "2"]);
    assert!(
        base.pixels().zip(doubled.pixels()).filter(|(b, d)| d[0] > b[0]).count() > 1_000,
        "scale 2 changed nothing"
    );

    let err = common::run_err(&["render", "--light-scale=-1", "--out", dir.join("x.png").to_str().unwrap()]);
    assert!(err.contains("--light-scale") && err.contains("-1"), "{err}");
    let err = common::run_err(&["render", "--light=point:range=-2", "--out", dir.join("x.png").to_str().unwrap()]);
    assert!(err.contains("range") && err.contains("-2"), "{err}");
    assert!(!dir.join("x.png").exists(), "a refused command wrote its output");
}
