//! Shadow maps and baked shadow textures per light (docs/shadow-textures.md, "Several
//! lights"): on the `lights` scene each light's shadow in the frame, read as the frame minus
//! the frame without that light, matches the outline CPU rays toward that light draw; the
//! atlas's baked channels hold each light's visibility; a point light inside the scene and a
//! fourth light in the atlas are named in the warning and still shade.

use crate::common;

use std::sync::Arc;

use common::ray_world::RayWorld;
use glam::{Vec2, Vec3};
use image::RgbaImage;
use nostencil::scene::lights::parse_light_spec;
use nostencil::scene::model::LightKind;
use nostencil::technique::shadow_atlas::atlas::mesh_atlas;
use nostencil::technique::shadow_atlas::maps::{self, Coverage};
use nostencil::technique::shadow_atlas::{self, ShadowAtlasOptions, ShadowKind, ShadowLightUniforms};
use nostencil::Gpu;
use nostencil::{builtin_scene, Scene, SceneLight};
use nostencil::{render_scene, RenderOptions, TechniqueFrame};

const SIZE: (u32, u32) = (160, 120);

fn frame(gpu: &Arc<Gpu>, scene: &Scene, technique: &str) -> TechniqueFrame {
    let options = RenderOptions {
        width: SIZE.0,
        height: SIZE.1,
        samples: 1,
        technique: common::technique(technique),
        ..RenderOptions::default()
    };
    let frame = render_scene(gpu, scene, &options).unwrap_or_else(|e| panic!("{technique} renders: {e}"));
    common::assert_no_validation_messages(gpu);
    frame
}

fn linear(image: &RgbaImage, i: usize) -> Vec3 {
    let p = image.as_raw();
    Vec3::new(common::srgb_decode(p[i * 4]), common::srgb_decode(p[i * 4 + 1]), common::srgb_decode(p[i * 4 + 2]))
}

fn intersection_over_union(a: &[bool], b: &[bool]) -> f64 {
    let both = a.iter().zip(b).filter(|(x, y)| **x && **y).count();
    let either = a.iter().zip(b).filter(|(x, y)| **x || **y).count();
    both as f64 / either.max(1) as f64
}

/// Whether a shadow-casting object lies between `point` and `light` (CPU rays).
fn occluded(world: &RayWorld, scene: &Scene, light: &SceneLight, point: Vec3, normal: Vec3) -> bool {
    let (dir, reach) = match light.kind {
        LightKind::Directional => (-light.direction.normalize(), f32::INFINITY),
        _ => ((light.position - point).normalize(), light.position.distance(point)),
    };
    let origin = point + normal * 2e-3 + dir * 2e-3;
    world.every_hit(origin, dir).iter().any(|(p, d)| *d > 1e-4 && *d < reach && scene.objects[p.object].casts_shadow)
}

/// The surface the camera sees through (x, y) of the frame: point and normal.
fn seen(scene: &Scene, world: &RayWorld, (x, y): (f32, f32)) -> Option<(Vec3, Vec3)> {
    let inverse = scene.camera.view_projection(SIZE.0 as f32 / SIZE.1 as f32).inverse();
    let ndc = |p: f32, side: u32| p / side as f32 * 2.0 - 1.0;
    let near = inverse.project_point3(Vec3::new(ndc(x, SIZE.0), ndc(y, SIZE.1), 0.0));
    let far = inverse.project_point3(Vec3::new(ndc(x, SIZE.0), ndc(y, SIZE.1), 0.5));
    let dir = (far - near).normalize();
    let hit = world.first_hit(near, dir)?;
    let object = &scene.objects[hit.object];
    let mesh = &scene.meshes[object.mesh].data;
    let t = &mesh.indices[hit.triangle * 3..hit.triangle * 3 + 3];
    let [a, b, c] = [0, 1, 2].map(|k| object.transform.transform_point3(mesh.positions[t[k] as usize]));
    let mut normal = (b - a).cross(c - a).normalize_or_zero();
    if normal.dot(dir) > 0.0 {
        normal = -normal;
    }
    Some((near + dir * hit.distance, normal))
}

/// Per light of the `lights` scene: where the frame lacks that light's term although the light
/// reaches the surface (frame minus the frame without the light, against the frame with the
/// light unshadowed) matches where CPU rays toward that light are blocked, IoU >= 0.9.
#[test]
fn each_lights_shadow_in_the_frame_is_where_rays_to_it_are_blocked() {
    let gpu = common::gpu();
    let scene = builtin_scene("lights").expect("scene");
    let coverage = maps::coverage(ShadowKind::Map, &scene);
    assert!(coverage.iter().all(|c| matches!(c, Coverage::Mapped { .. })), "{coverage:?}");
    let all = frame(&gpu, &scene, "shadow-map");
    assert!(all.warnings.is_empty(), "{:?}", all.warnings);
    let world = RayWorld::of(&scene);
    let pixels = (SIZE.0 * SIZE.1) as usize;
    let surfaces: Vec<Option<(Vec3, Vec3)>> = (0..pixels)
        .map(|i| seen(&scene, &world, ((i as u32 % SIZE.0) as f32 + 0.5, (i as u32 / SIZE.0) as f32 + 0.5)))
        .collect();
    for (index, light) in scene.lights.iter().enumerate() {
        let mut without = scene.clone();
        without.lights.remove(index);
        let mut unshadowed = scene.clone();
        unshadowed.lights[index].casts_shadow = false;
        let without = frame(&gpu, &without, "shadow-map").output.image;
        let unshadowed = frame(&gpu, &unshadowed, "shadow-map").output.image;
        let (mut mask, mut truth) = (vec![false; pixels], vec![false; pixels]);
        let mut reached = 0;
        for i in 0..pixels {
            let Some((point, normal)) = surfaces[i] else { continue };
            // The light's term at full strength, and as the frame has it.
            let full = (linear(&unshadowed, i) - linear(&without, i)).element_sum();
            if full < 0.03 {
                continue;
            }
            reached += 1;
            let term = (linear(&all.output.image, i) - linear(&without, i)).element_sum();
            mask[i] = term < 0.5 * full;
            truth[i] = occluded(&world, &scene, light, point, normal);
        }
        let iou = intersection_over_union(&mask, &truth);
        let shadowed = truth.iter().filter(|&&t| t).count();
        println!("'{}': {reached} pixels it reaches, {shadowed} shadowed by rays, IoU {iou:.3}", light.name);
        assert!(shadowed > 150, "'{}' casts too small a shadow to measure: {shadowed}", light.name);
        assert!(iou >= 0.9, "'{}': IoU {iou:.3} against the rays", light.name);
    }
}

/// Each texel's surface point and normal in world space, from the object's atlas layout (the
/// one the renderer lays out): every atlas triangle rasterised over the texel centres it covers.
fn texel_surfaces(scene: &Scene, object: usize, side: u32) -> Vec<Option<(Vec3, Vec3)>> {
    let o = &scene.objects[object];
    let mesh = &scene.meshes[o.mesh];
    let size = ShadowAtlasOptions::default().texture_size;
    let atlas = mesh_atlas(&mesh.name, &mesh.data, mesh.uv1.as_deref(), size).expect("atlas");
    let normal_matrix = o.transform.inverse().transpose();
    let mut surfaces = vec![None; (side * side) as usize];
    for t in atlas.indices.chunks_exact(3) {
        let uv = [0, 1, 2].map(|k| atlas.uvs[t[k] as usize] * side as f32);
        let area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
        if area.abs() < 1e-9 {
            continue;
        }
        let (lo, hi) = (uv[0].min(uv[1]).min(uv[2]), uv[0].max(uv[1]).max(uv[2]));
        for y in lo.y.floor().max(0.0) as u32..(hi.y.ceil() as u32).min(side) {
            for x in lo.x.floor().max(0.0) as u32..(hi.x.ceil() as u32).min(side) {
                let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let w = [(1, 2), (2, 0), (0, 1)].map(|(i, j)| (uv[j] - uv[i]).perp_dot(p - uv[i]) / area);
                if w.iter().any(|&w| w < 0.0) {
                    continue;
                }
                let blend = |v: [Vec3; 3]| v[0] * w[0] + v[1] * w[1] + v[2] * w[2];
                let position = blend([0, 1, 2].map(|k| atlas.positions[t[k] as usize]));
                let normal = blend([0, 1, 2].map(|k| atlas.normals[t[k] as usize]));
                surfaces[(y * side + x) as usize] = Some((
                    o.transform.transform_point3(position),
                    normal_matrix.transform_vector3(normal).normalize_or_zero(),
                ));
            }
        }
    }
    surfaces
}

/// The baked texture of every object of the `lights` scene holds light i's visibility in
/// channel i: read back, against CPU rays toward that light, on texels the light faces (N.L >=
/// 0.3), inside its map, cone and range, away from shadow edges (the answer the same 2 texels
/// away all round).
#[test]
fn the_atlas_bakes_each_lights_visibility_in_its_own_channel() {
    let gpu = common::gpu();
    let scene = builtin_scene("lights").expect("scene");
    let options = RenderOptions { width: 64, height: 64, ..RenderOptions::default() };
    let baked = shadow_atlas::bake(&gpu, &scene, &options, &mut |_| {}).expect("bake");
    let coverage = maps::coverage(ShadowKind::Atlas, &scene);
    assert_eq!(coverage.iter().map(|c| c.layer()).collect::<Vec<_>>(), [Some(0), Some(1), Some(2)]);
    let map_size = ShadowAtlasOptions::default().map_size;
    let views = ShadowLightUniforms::fitted(&scene, &scene.light(), &coverage, map_size);
    let world = RayWorld::of(&scene);
    let mut counts = vec![[0usize; 2]; scene.lights.len()];
    let mut wrong = Vec::new();
    for (index, object) in scene.objects.iter().enumerate() {
        let texture = baked.read_shadow_texture(index, 0).expect("read back");
        let side = texture.width();
        let surfaces = texel_surfaces(&scene, index, side);
        for (c, light) in scene.lights.iter().enumerate() {
            let view = views.lights[c].view_proj;
            // None: not a test of this light's occlusion; else whether a ray finds a caster.
            let answer = |x: i64, y: i64| -> Option<bool> {
                let (x, y) = (u32::try_from(x).ok()?, u32::try_from(y).ok()?);
                let (point, normal) = (*surfaces.get((y * side + x) as usize)?)?;
                let toward = match light.kind {
                    LightKind::Directional => -light.direction.normalize(),
                    _ => (light.position - point).normalize(),
                };
                let clip = view * point.extend(1.0);
                let uv = Vec2::new(clip.x, clip.y) / clip.w * 0.5 + 0.5;
                let in_map = clip.w > 0.0 && uv.cmpge(Vec2::splat(0.02)).all() && uv.cmple(Vec2::splat(0.98)).all();
                let in_cone = match light.kind {
                    LightKind::Spot { outer_cone_angle, .. } => {
                        light.direction.normalize().dot(-toward) > (outer_cone_angle * 0.95).cos()
                    }
                    _ => true,
                };
                let in_range = light.range.is_none_or(|r| light.position.distance(point) < r * 0.95);
                (normal.dot(toward) >= 0.3 && in_map && in_cone && in_range)
                    .then(|| occluded(&world, &scene, light, point, normal))
            };
            for y in 0..side as i64 {
                for x in 0..side as i64 {
                    let Some(here) = answer(x, y) else { continue };
                    let robust = (-1..=1).all(|dy| (-1..=1).all(|dx| answer(x + 2 * dx, y + 2 * dy) == Some(here)));
                    if !robust {
                        continue;
                    }
                    counts[c][usize::from(here)] += 1;
                    let value = texture.get_pixel(x as u32, y as u32).0[c];
                    if (here && value >= 55) || (!here && value <= 200) {
                        wrong.push(format!("{} texel ({x}, {y}) channel {c}: {value}, shadowed {here}", object.name));
                    }
                }
            }
        }
    }
    for (light, [lit, shadowed]) in scene.lights.iter().zip(&counts) {
        println!("'{}': {lit} lit and {shadowed} shadowed texels checked", light.name);
        assert!(*lit > 1000 && *shadowed > 100, "'{}': {lit} lit, {shadowed} shadowed", light.name);
    }
    // The few texels off lie on the ground inside the pillar's foot, hidden: their ray starts
    // inside the pillar, their map compare sees its bottom face at the ground's depth.
    let checked: usize = counts.iter().flatten().sum();
    println!("{} of {checked} texels wrong: {:?}", wrong.len(), &wrong[..wrong.len().min(8)]);
    assert!(wrong.len() * 1000 <= checked, "{} of {checked} texels wrong", wrong.len());
    common::assert_no_validation_messages(&gpu);
}

/// A point light inside the scene's box gets no map (no cube maps): the warning names it, and
/// only it, with the reason, and it still lights the frame (unshadowed). A fourth shadowing
/// light fits the shadow map's array but not a baked texel: the atlas names it.
#[test]
fn lights_left_unshadowed_are_named_and_still_shade() {
    let gpu = common::gpu();
    let base = builtin_scene("lights").expect("scene");
    let mut scene = base.clone();
    scene
        .lights
        .push(parse_light_spec("point:name=bulb:at=0.6,0.9,1.6:colour=0.1,1,0.1:intensity=3:range=4").expect("spec"));
    for technique in ["shadow-map", "shadow-texture-atlas"] {
        let with = frame(&gpu, &scene, technique);
        let warning = with.warnings.join("\n");
        assert!(
            warning.contains("shadows 'sun', 'lamp', 'spot': 'bulb' (a point light inside the scene's bounds")
                && warning.contains("no cube maps) shades unshadowed"),
            "{technique}: {warning}"
        );
        let without = frame(&gpu, &base, technique).output.image;
        let greener = (0..(SIZE.0 * SIZE.1) as usize)
            .filter(|&i| linear(&with.output.image, i).y - linear(&without, i).y > 0.02)
            .count();
        println!("{technique}: the bulb brightens {greener} pixels");
        assert!(greener > 1000, "{technique}: the bulb brightens only {greener} pixels");
    }

    let mut four = base.clone();
    four.lights.push(parse_light_spec("directional:name=moon:dir=-0.4,-1,0.3:intensity=0.2").expect("spec"));
    assert!(frame(&gpu, &four, "shadow-map").warnings.is_empty());
    let warning = frame(&gpu, &four, "shadow-texture-atlas").warnings.join("\n");
    assert!(warning.contains("'moon' (a baked texel holds the shadows of 3 lights) shades unshadowed"), "{warning}");
}

/// The warning about lights left unshadowed tells how to shadow them all: a technique that
/// shadows every light in the additive mode names that mode, the others point to `nostencil
/// info`, which lists the techniques that do (derived from each technique's own
/// `shadowed_lights`: `registry::shadowing_every_light`).
#[test]
fn the_unshadowed_lights_warning_names_the_way_to_shadow_them_all() {
    use nostencil::ShadowMode;
    let gpu = common::gpu();
    let scene = builtin_scene("lights").expect("scene");
    for (technique, fix) in [
        ("shadow-volume", "(--shadow-mode additive shadows every light)"),
        ("planar", "(--shadow-mode additive shadows every light)"),
        ("blob", "(`nostencil info` lists the techniques that shadow every light)"),
    ] {
        let mut options = RenderOptions {
            width: SIZE.0,
            height: SIZE.1,
            samples: 1,
            technique: common::technique(technique),
            ..RenderOptions::default()
        };
        options.shadow_mode = ShadowMode::Modulate;
        let frame = render_scene(&gpu, &scene, &options).unwrap_or_else(|e| panic!("{technique}: {e}"));
        let warning = frame.warnings.join("\n");
        assert!(warning.contains("'lamp', 'spot' shade unshadowed") && warning.contains(fix), "{technique}: {warning}");
        // In the additive loop the two families shadow every light and say nothing.
        if technique != "blob" {
            options.shadow_mode = ShadowMode::Additive;
            let frame = render_scene(&gpu, &scene, &options).expect("additive");
            assert!(frame.warnings.iter().all(|w| !w.contains("unshadowed")), "{technique}: {:?}", frame.warnings);
        }
    }
    common::assert_no_validation_messages(&gpu);
}

/// A scene whose one light casts no shadows: no light has a map, the array's one layer is
/// cleared all the same (bound, never weighed), and every technique of the family draws the
/// `lit` frame, with no validation message.
#[test]
fn a_light_without_shadows_leaves_the_lit_frame() {
    let gpu = common::gpu();
    let mut scene = builtin_scene("box").expect("scene");
    scene.lights[0].casts_shadow = false;
    let lit = frame(&gpu, &scene, "lit").output.image;
    for technique in ["shadow-map", "shadow-texture-atlas", "projective-texture"] {
        let frame = frame(&gpu, &scene, technique);
        assert!(frame.warnings.is_empty(), "{technique}: {:?}", frame.warnings);
        assert_eq!(frame.output.image, lit, "{technique}");
    }
}

/// `passes --scene` plans what the renderer runs: the bulb, a point light inside the scene's
/// box, gets no map pass in the printed plan, as in the profiled frame.
#[test]
fn passes_prints_no_map_pass_for_a_light_left_unshadowed() {
    let bulb = "point:name=bulb:at=0.6,0.9,1.6:colour=0.1,1,0.1:intensity=3:range=4";
    let mapped = |names: Vec<String>| {
        let mut maps: Vec<String> = names.into_iter().filter(|n| n.ends_with(": shadow map")).collect();
        maps.dedup();
        maps
    };
    let expected = ["sun: shadow map", "lamp: shadow map", "spot: shadow map"];
    for technique in ["shadow-map", "shadow-texture-atlas"] {
        let (table, _) = common::run_ok(&["passes", "--technique", technique, "--scene", "lights", "--light", bulb]);
        // The plan with a moving light, its rows' second column.
        let moving = table.split("(moving light)").nth(1).and_then(|t| t.split("\n### ").next());
        let moving = moving.expect("a moving-light plan");
        let planned = mapped(moving.lines().filter_map(|l| l.split('|').nth(2)).map(|c| c.trim().to_owned()).collect());
        assert_eq!(planned, expected, "{technique}:\n{table}");

        let (json, stderr) = common::run_ok(&[
            "profile",
            "--validation",
            "--technique",
            technique,
            "--scene",
            "lights",
            "--light",
            bulb,
            "--light-motion",
            "moving",
            "--size",
            "64x48",
            "--samples",
            "1",
            "--format",
            "json",
        ]);
        let report: serde_json::Value = serde_json::from_str(&json).expect("JSON");
        let ran = report["passes"].as_array().expect("passes").iter();
        let profiled = mapped(ran.map(|p| p["name"].as_str().unwrap_or("").to_owned()).collect());
        assert_eq!(profiled, expected, "{technique}:\n{json}");
        assert!(!stderr.contains("vulkan validation"), "{technique}: {stderr}");
    }
}
