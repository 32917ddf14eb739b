//! Shadow textures baked into per-model atlases (seed 004): a concave model shadows itself in
//! its baked texture (checked against CPU ray casts), atlas-125's baked textures and rendered
//! frame are shadowed where CPU ray casts say, the atlas and shadow-map renders agree except
//! along shadow edges, and no mip of a generated atlas bleeds across chart borders.

use crate::common::{self, technique};

use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3};
use image::RgbaImage;
use nostencil::mesh::geometry_image::{geometry_image, horned_radius, octahedral_direction};
use nostencil::mesh::ray::ray_hits_triangle;
use nostencil::mesh::{shapes, MeshData};
use nostencil::technique::shadow_atlas::atlas::{mesh_atlas, AtlasSource};
use nostencil::technique::shadow_atlas::{self, Baked, LightMode, ShadowAtlasOptions, ShadowAtlasStats, ShadowKind};
use nostencil::Gpu;
use nostencil::StencilMode;
use nostencil::{builtin_scene, Camera, Light, Scene};
use nostencil::{render_scene, RenderOptions, Technique};

use common::ray_world::RayWorld;

fn scene_of(name: &str, light: Light, meshes: Vec<(&str, MeshData, Mat4)>) -> Scene {
    let mut scene = Scene::empty(name, Camera::look_at(Vec3::new(0.0, 2.0, 5.0), Vec3::ZERO), light);
    for (name, mesh, transform) in meshes {
        let index = scene.add_mesh(name, mesh);
        scene.add_object(name, index, transform, Vec3::new(0.8, 0.6, 0.4), true);
    }
    scene
}

fn bake<'s>(gpu: &Arc<Gpu>, scene: &'s Scene, options: ShadowAtlasOptions) -> Baked<'s> {
    let options = RenderOptions {
        width: 64,
        height: 64,
        stencil: StencilMode::Emulated,
        shadow_atlas: options,
        ..Default::default()
    };
    shadow_atlas::bake(gpu, scene, &options, &mut |_| {}).expect("atlas bake")
}

#[test]
fn concave_model_shadows_itself_in_its_baked_texture() {
    let gpu = common::gpu();
    // A 64x64 geometry image with a tall horn leaning over the body: under a slanting light its
    // shadow falls on the lit side of the body.
    let horns = [(Vec3::new(0.0, 1.0, 0.0), 1.6), (Vec3::new(1.0, 0.2, 0.0), 1.2)];
    let radius = horned_radius(&horns);
    let mesh = geometry_image(64, &radius).expect("geometry image");
    let direction = Vec3::new(0.5, -1.0, 0.1).normalize();
    let scene = scene_of("concave", Light::Directional { direction }, vec![("horned", mesh.clone(), Mat4::IDENTITY)]);
    let renderer = bake(&gpu, &scene, ShadowAtlasOptions::default());
    assert_eq!(renderer.atlases()[0].source, AtlasSource::GeometryImage { n: 64 });
    let texture = renderer.read_shadow_texture(0, 0).expect("read back");
    assert_eq!(texture.dimensions(), (64, 64));

    // CPU answer per texel: the surface point at the texel centre, its normal, and a ray cast
    // towards the light against every triangle.
    let surface = |uv: Vec2| {
        let d = octahedral_direction(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0);
        d * radius(d)
    };
    let triangles: Vec<[Vec3; 3]> =
        mesh.indices.chunks_exact(3).map(|t| [0, 1, 2].map(|k| mesh.positions[t[k] as usize])).collect();
    let to_light = -direction;
    // Texel (x, y) covers grid coordinates around ((x + 0.5) / 64) * 63 / 63 in uv.
    let classify = |x: u32, y: u32| -> Option<bool> {
        let uv = Vec2::new((x as f32 + 0.5) / 64.0, (y as f32 + 0.5) / 64.0);
        let e = 0.5 / 64.0;
        let p = surface(uv);
        let du = surface(uv + Vec2::new(e, 0.0)) - surface(uv - Vec2::new(e, 0.0));
        let dv = surface(uv + Vec2::new(0.0, e)) - surface(uv - Vec2::new(0.0, e));
        let mut n = du.cross(dv).normalize_or_zero();
        if n.dot(p) < 0.0 {
            n = -n;
        }
        let n_dot_l = n.dot(to_light);
        if n_dot_l < 0.2 {
            return None; // facing away or grazing: not a test of occlusion
        }
        let origin = p + n * 0.02;
        Some(!triangles.iter().any(|t| ray_hits_triangle(origin, to_light, *t).is_some_and(|d| d > 1e-4)))
    };
    let answers: Vec<Option<bool>> = (0..64 * 64).map(|i| classify(i % 64, i / 64)).collect();
    let (mut lit_ok, mut lit_total, mut shadow_ok, mut shadow_total) = (0, 0, 0, 0);
    for y in 1..63u32 {
        for x in 1..63u32 {
            let Some(lit) = answers[(y * 64 + x) as usize] else { continue };
            // Robust texels only: all 8 neighbours have the same answer (no edge nearby).
            let robust = (-1i32..=1)
                .all(|dy| (-1i32..=1).all(|dx| answers[((y as i32 + dy) * 64 + x as i32 + dx) as usize] == Some(lit)));
            if !robust {
                continue;
            }
            let baked = texture.get_pixel(x, y).0[0];
            if lit {
                lit_total += 1;
                lit_ok += (baked > 200) as u32;
            } else {
                shadow_total += 1;
                shadow_ok += (baked < 55) as u32;
            }
        }
    }
    println!("self-shadow: {shadow_ok}/{shadow_total} occluded texels dark, {lit_ok}/{lit_total} unoccluded lit");
    assert!(shadow_total >= 20, "the shape must shadow itself on lit-facing texels: {shadow_total} found");
    assert!(lit_total >= 200, "{lit_total} lit texels");
    assert_eq!(shadow_ok, shadow_total, "occluded texels baked as lit");
    assert_eq!(lit_ok, lit_total, "unoccluded texels baked as shadowed");
    common::assert_no_validation_messages(&gpu);
}

fn render(gpu: &Arc<Gpu>, scene: &Scene, technique: Technique, size: (u32, u32)) -> RgbaImage {
    let options = RenderOptions {
        width: size.0,
        height: size.1,
        technique,
        shadow_atlas: ShadowAtlasOptions { light: LightMode::Moving, ..Default::default() },
        ..Default::default()
    };
    render_scene(gpu, scene, &options).expect("frame").output.image
}

/// Renders `scene` with the baked atlas and with the shadow map and checks that they differ
/// only along shadow edges (the two sample the light's depth at different places: texels of
/// the shadow texture against pixels of the frame). Under several lights an edge is where the
/// set of lights whose shadow falls on a pixel changes: light i's shadow is where the map frame
/// differs from the map frame with light i unshadowed.
fn assert_atlas_agrees_with_shadow_map(gpu: &Arc<Gpu>, scene: &Scene, size: (u32, u32)) {
    let atlas = render(gpu, scene, technique("shadow-texture-atlas"), size);
    let map = render(gpu, scene, technique("shadow-map"), size);
    let lit = render(gpu, scene, technique("lit"), size);
    // Kept for a person to look at.
    let dir = common::scratch_dir(&format!("atlas-vs-map-{}", scene.name));
    for (image, name) in [(&atlas, "atlas"), (&map, "shadow-map"), (&lit, "lit")] {
        nostencil::write_png(image, &dir.join(format!("{name}.png")), false).expect("write png");
    }
    let (w, h) = size;
    // The shadow map's shadow: pixels darker than the unshadowed frame.
    let shadowed = |x: u32, y: u32| map.get_pixel(x, y).0[..3] != lit.get_pixel(x, y).0[..3];
    // Per pixel, bit i: light i's shadow falls there (one light: the map's shadow itself).
    let mut shadows = vec![0u32; (w * h) as usize];
    if scene.lights.len() == 1 {
        shadows.iter_mut().enumerate().for_each(|(i, s)| *s = shadowed(i as u32 % w, i as u32 / w) as u32);
    }
    for (index, _) in scene.lights.iter().enumerate().filter(|(_, l)| l.casts_shadow && scene.lights.len() > 1) {
        let mut without = scene.clone();
        without.lights[index].casts_shadow = false;
        let unshadowed = render(gpu, &without, technique("shadow-map"), size);
        for (i, s) in shadows.iter_mut().enumerate() {
            let (x, y) = (i as u32 % w, i as u32 / w);
            *s |= u32::from(map.get_pixel(x, y).0[..3] != unshadowed.get_pixel(x, y).0[..3]) << index;
        }
    }
    let shadows_at = |x: u32, y: u32| shadows[(y * w + x) as usize];
    let differs = |x: u32, y: u32| {
        let (a, b) = (atlas.get_pixel(x, y).0, map.get_pixel(x, y).0);
        (0..3).any(|c| a[c].abs_diff(b[c]) > 6)
    };
    let near_edge = |x: u32, y: u32, r: i32| {
        let here = shadows_at(x, y);
        (-r..=r).any(|dy| {
            (-r..=r).any(|dx| {
                let (nx, ny) = (x as i32 + dx, y as i32 + dy);
                nx >= 0 && ny >= 0 && nx < w as i32 && ny < h as i32 && shadows_at(nx as u32, ny as u32) != here
            })
        })
    };
    let (mut differing, mut off_edge, mut shadow_pixels) = (0u32, 0u32, 0u32);
    for y in 0..h {
        for x in 0..w {
            shadow_pixels += shadowed(x, y) as u32;
            if differs(x, y) {
                differing += 1;
                if !near_edge(x, y, 3) {
                    off_edge += 1;
                }
            }
        }
    }
    let total = w * h;
    let name = &scene.name;
    println!(
        "{name}: atlas vs shadow map: {differing} of {total} pixels differ ({:.2}%), {off_edge} of them more \
         than 3 px from a shadow edge; {shadow_pixels} shadowed pixels",
        100.0 * differing as f64 / total as f64
    );
    assert!(shadow_pixels > total / 50, "{name}: the scene must show shadows: {shadow_pixels}");
    assert!((differing as f64) < 0.04 * total as f64, "{name}: {differing} differing pixels");
    assert!((off_edge as f64) < 0.002 * total as f64, "{name}: {off_edge} differing pixels away from shadow edges");
}

#[test]
fn atlas_and_shadow_map_agree_except_along_shadow_edges() {
    let gpu = common::gpu();
    assert_atlas_agrees_with_shadow_map(&gpu, &builtin_scene("atlas-one").expect("scene"), (160, 120));
    common::assert_no_validation_messages(&gpu);
}

/// Three lights (a sun, a point lamp and a spot whose shadows overlap): the atlas bakes each in
/// its own channel, the shadow map samples each in its own layer, and the frames agree but
/// along shadow edges.
#[test]
fn atlas_and_shadow_map_agree_except_along_shadow_edges_under_three_lights() {
    let gpu = common::gpu();
    assert_atlas_agrees_with_shadow_map(&gpu, &builtin_scene("lights").expect("scene"), (160, 120));
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn generated_atlases_of_dense_meshes_agree_with_the_shadow_map() {
    // Meshes with no usable UVs and far more triangles than a 256^2 texture has room for one
    // chart each: a smooth sphere (18,432 triangles), a self-shadowing torus knot, and a flat
    // box as the ground (its UVs overlap, so it is generated too).
    let gpu = common::gpu();
    let without_uvs = |mut mesh: MeshData| {
        mesh.uvs.clear();
        mesh
    };
    let sphere = without_uvs(shapes::uv_sphere(96, 96).expect("sphere"));
    let knot = without_uvs(shapes::torus_knot(2, 3, 0.6, 0.18, 256, 16).expect("knot"));
    let light = Light::Directional { direction: Vec3::new(-0.4, -1.0, -0.3).normalize() };
    let scene = scene_of(
        "dense-generated",
        light,
        vec![
            ("ground", shapes::cube(1.0), Mat4::from_scale(Vec3::new(8.0, 0.1, 8.0))),
            ("sphere", sphere, Mat4::from_translation(Vec3::new(-1.2, 0.8, 0.0)) * Mat4::from_scale(Vec3::splat(0.7))),
            ("knot", knot, Mat4::from_translation(Vec3::new(1.1, 1.0, 0.0))),
        ],
    );
    let renderer = bake(&gpu, &scene, ShadowAtlasOptions::default());
    for info in renderer.atlases() {
        let AtlasSource::Generated { charts, padding } = info.source else {
            panic!("{}: {:?} instead of a generated atlas", info.mesh, info.source);
        };
        println!("{}: {charts} charts, {padding} texels padding", info.mesh);
        assert_eq!(padding, 4, "{}", info.mesh);
    }
    drop(renderer);
    assert_atlas_agrees_with_shadow_map(&gpu, &scene, (160, 120));
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn no_mip_bleeds_across_chart_borders() {
    let gpu = common::gpu();
    // A cube lit from straight above: the top face's two charts are lit, the side and bottom
    // charts (normal . light <= 0) fully shadowed, and they sit next to each other in the
    // generated atlas (its UVs overlap: every face uses the whole square).
    let cube = shapes::cube(1.0);
    let atlas = mesh_atlas("cube", &cube, None, 128).expect("atlas");
    assert!(matches!(atlas.source, AtlasSource::Generated { .. }), "{:?}", atlas.source);
    let scene =
        scene_of("charts", Light::Directional { direction: Vec3::NEG_Y }, vec![("cube", cube.clone(), Mat4::IDENTITY)]);
    let renderer = bake(&gpu, &scene, ShadowAtlasOptions { texture_size: 128, ..Default::default() });
    let info = &renderer.atlases()[0];
    assert!(info.mip_levels >= 3, "{} mips", info.mip_levels);
    let mut checked = 0;
    for mip in 0..info.mip_levels {
        let texture = renderer.read_shadow_texture(0, mip).expect("read back");
        let side = texture.width() as f32;
        for (chart, t) in atlas.indices.chunks_exact(3).enumerate() {
            let uv = [0, 1, 2].map(|k| atlas.uvs[t[k] as usize] * side);
            let lit = cube.normals[cube.indices[chart * 3] as usize].y > 0.5;
            let area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]);
            // Every texel whose centre lies in the chart, border texels included.
            for y in 0..texture.height() {
                for x in 0..texture.width() {
                    let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                    let inside = [(1, 2), (2, 0), (0, 1)]
                        .iter()
                        .all(|&(i, j)| (uv[j] - uv[i]).perp_dot(p - uv[i]) / area >= 0.0);
                    if !inside {
                        continue;
                    }
                    checked += 1;
                    let value = texture.get_pixel(x, y).0[0];
                    if lit {
                        assert!(value >= 250, "mip {mip}: lit chart {chart} texel ({x}, {y}) = {value}");
                    } else {
                        assert!(value <= 5, "mip {mip}: shadowed chart {chart} texel ({x}, {y}) = {value}");
                    }
                }
            }
        }
    }
    assert!(checked > 500, "{checked} texels checked");
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn fixed_light_skips_the_shadow_passes_and_moving_light_does_not() {
    let gpu = common::gpu();
    let scene = scene_of(
        "box",
        Light::Directional { direction: Vec3::new(0.3, -1.0, 0.2).normalize() },
        vec![("box", shapes::cube(1.0), Mat4::IDENTITY)],
    );
    for (light, kind) in [LightMode::Fixed, LightMode::Moving]
        .into_iter()
        .flat_map(|l| [ShadowKind::Atlas, ShadowKind::Map].map(move |k| (l, k)))
    {
        let options = RenderOptions {
            width: 64,
            height: 64,
            stencil: StencilMode::Emulated,
            technique: kind.technique(),
            shadow_atlas: ShadowAtlasOptions { light, texture_size: 64, map_size: 64, ..Default::default() },
            ..Default::default()
        };
        let mut renderer = kind.technique().build(&gpu, &scene, &options).expect("renderer");
        let first = renderer.frame_with(&scene).expect("frame 1");
        let second = renderer.frame_with(&scene).expect("frame 2");
        let names =
            |f: &nostencil::TechniqueFrame| f.output.counters.passes.iter().map(|p| p.name.clone()).collect::<Vec<_>>();
        let cached = |f: &nostencil::TechniqueFrame| f.stats::<ShadowAtlasStats>().expect("atlas stats").cached;
        assert!(!cached(&first) && names(&first).contains(&"sun: shadow map".to_string()));
        assert_eq!(cached(&second), light == LightMode::Fixed, "{light:?} {kind:?}");
        assert_eq!(names(&second).contains(&"sun: shadow map".to_string()), light == LightMode::Moving);
        assert_eq!(
            names(&second).contains(&"atlas bake".to_string()),
            light == LightMode::Moving && kind == ShadowKind::Atlas
        );
        assert_eq!(first.output.image.dimensions(), second.output.image.dimensions());
        if light == LightMode::Fixed {
            assert_eq!(first.output.image, second.output.image, "a cached frame is the same frame");
        }
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn texcoord1_is_used_when_it_does_not_overlap_and_replaced_when_it_does() {
    let path = common::test_asset("CornellBox.glb");
    let scene = nostencil::scene_from_gltf(&path, 0.0).expect("CornellBox.glb");
    let with_uv1: Vec<_> = scene.meshes.iter().filter(|m| m.uv1.is_some()).collect();
    assert!(!with_uv1.is_empty(), "CornellBox.glb has TEXCOORD_1");
    for mesh in &with_uv1 {
        let atlas = mesh_atlas(&mesh.name, &mesh.data, mesh.uv1.as_deref(), 256).expect("atlas");
        assert_eq!(atlas.source, AtlasSource::TexCoord1, "{}: {:?}", mesh.name, atlas.rejected_uv1);
        assert_eq!(atlas.uvs, *mesh.uv1.as_ref().expect("uv1"));
    }
    // The same mesh with every triangle's TEXCOORD_1 folded onto one corner of the square.
    let mesh = with_uv1.iter().max_by_key(|m| m.data.indices.len()).expect("a mesh");
    let folded: Vec<Vec2> = mesh.uv1.as_ref().expect("uv1").iter().map(|uv| *uv * 0.25).collect();
    let mut overlapping = mesh.data.clone();
    // Duplicate the triangles so that each covers the texels of its twin.
    let twins: Vec<u32> = overlapping.indices.clone();
    overlapping.indices.extend(twins);
    let atlas = mesh_atlas("folded", &overlapping, Some(&folded), 256).expect("atlas");
    assert_ne!(atlas.source, AtlasSource::TexCoord1);
    assert!(atlas.rejected_uv1.as_deref().is_some_and(|r| r.contains("covered twice")), "{:?}", atlas.rejected_uv1);
}

/// The ray casts' hierarchy answers as testing every triangle does: nearest hits (object and
/// distance) and occluders of camera and shadow rays over atlas-one.
/// Every triangle of the scene in world space, with the index of its object.
fn world_triangles(scene: &nostencil::Scene) -> Vec<(usize, [Vec3; 3])> {
    scene
        .objects
        .iter()
        .enumerate()
        .flat_map(|(i, o)| {
            let mesh = &scene.meshes[o.mesh].data;
            mesh.indices
                .chunks_exact(3)
                .map(move |t| (i, [0, 1, 2].map(|k| o.transform.transform_point3(mesh.positions[t[k] as usize]))))
        })
        .collect()
}

// The tests by topic, beside those above.
#[path = "shadow_atlas/bake_cli_and_table1.rs"]
mod bake_cli_and_table1;
#[path = "shadow_atlas/flicker_and_projective.rs"]
mod flicker_and_projective;
#[path = "shadow_atlas/ray_cast.rs"]
mod ray_cast;
