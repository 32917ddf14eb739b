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

#[test]
fn bake_writes_the_models_shadow_texture_from_the_command_line() {
    let dir = common::scratch_dir("bake-cli");
    let out = dir.join("model.png");
    let (_, err) = common::run_ok(&["bake", "--scene", "atlas-one", "--out", out.to_str().unwrap()]);
    assert!(err.contains("of 'model'") && err.contains("geometry image 257x257"), "{err}");
    // The horned sphere shadows itself: its texture holds lit and shadowed texels.
    let texture = common::read_png(&out);
    assert_eq!(texture.dimensions(), (256, 256));
    let lit = texture.pixels().filter(|p| p[0] == 255).count();
    let shadowed = texture.pixels().filter(|p| p[0] == 0).count();
    assert!(lit > 256 * 256 / 10 && shadowed > 256 * 256 / 10, "{lit} lit, {shadowed} shadowed texels");

    let mip = dir.join("mip2.png");
    common::run_ok(&[
        "bake",
        "--scene",
        "atlas-one",
        "--model",
        "ground",
        "--mip",
        "2",
        "--out",
        mip.to_str().unwrap(),
    ]);
    let ground = common::read_png(&mip);
    assert_eq!(ground.dimensions(), (64, 64));
    // The ground is lit, but for the model's shadow on it.
    let lit = ground.pixels().filter(|p| p[0] == 255).count();
    let shadowed = ground.pixels().filter(|p| p[0] == 0).count();
    assert!(lit > 64 * 64 / 2 && shadowed > 20, "{lit} lit, {shadowed} shadowed texels at mip 2");

    let missing = dir.join("none.png");
    let err =
        common::run_err(&["bake", "--scene", "atlas-one", "--model", "teapot", "--out", missing.to_str().unwrap()]);
    assert!(err.contains("no model 'teapot'") && err.contains("ground, model"), "{err}");
    assert!(!missing.exists());

    // 400 separate triangles cannot be laid out in a 16x16 texture: the error follows the
    // progress line on a line of its own, and no file is written.
    let mut positions = Vec::new();
    for i in 0..400u32 {
        let (x, z) = ((i % 20) as f32 * 2.0, (i / 20) as f32 * 2.0);
        for p in [[x, 1.0, z], [x, 1.0, z + 1.0], [x + 1.0, 1.0, z]] {
            positions.extend(p.iter().flat_map(|c: &f32| c.to_le_bytes()));
        }
    }
    std::fs::write(dir.join("confetti.bin"), &positions).expect("write bin");
    let gltf = serde_json::json!({
        "asset": { "version": "2.0" },
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 } }] }],
        "buffers": [{ "uri": "confetti.bin", "byteLength": positions.len() }],
        "bufferViews": [{ "buffer": 0, "byteLength": positions.len() }],
        "accessors": [{ "bufferView": 0, "componentType": 5126, "count": 1200, "type": "VEC3",
            "min": [0.0, 1.0, 0.0], "max": [39.0, 1.0, 39.0] }]
    });
    let scene = dir.join("confetti.gltf");
    std::fs::write(&scene, serde_json::to_vec(&gltf).expect("json")).expect("write gltf");
    let out = dir.join("confetti.png");
    let err = common::run_err(&[
        "bake",
        "--scene",
        scene.to_str().unwrap(),
        "--shadow-texture-size",
        "16",
        "--out",
        out.to_str().unwrap(),
    ]);
    let last = err.trim_end().lines().last().unwrap_or_default();
    assert!(last.starts_with("nostencil: error:") && last.contains("400 atlas charts do not fit"), "{err:?}");
    assert!(!out.exists());
}

#[test]
fn table1_is_recorded_beside_the_papers_values() {
    let dir = common::scratch_dir("table1");
    let out = dir.join("recorded");
    let args = ["bench", "--technique", "shadow-texture-atlas", "--size", "48x48", "--warmup", "1", "--runs", "3"];
    // No --validation: its per-call cost lands on both lights and blurs the timing this test
    // compares; the same frames run under validation in the other atlas tests.
    let (text, _) = common::run_ok(&[&args[..], &["--table1-out", out.to_str().unwrap()]].concat());
    assert!(text.contains("paper fps"), "{text}");

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("table1.json")).expect("table1.json")).expect("JSON");
    assert_eq!(json["schema"], "nostencil-table1/3");
    assert_eq!((json["width"].as_u64(), json["runs"].as_u64()), (Some(48), Some(3)));
    let rows = json["rows"].as_array().expect("rows");
    // Two scenes x two techniques x two lights, each with the paper's value beside it.
    assert_eq!(rows.len(), 8, "{json}");
    let paper = shadow_atlas_paper_values();
    for row in rows {
        for column in ["scene", "technique", "light", "fps", "frame_ms", "gpu_ms", "passes", "paper_fps"] {
            assert!(!row[column].is_null(), "row without {column}: {row}");
        }
        assert_eq!(row["frame_ms_rounds"].as_array().map(Vec::len), Some(3), "{row}");
        let key = (row["scene"].as_str().unwrap_or(""), row["technique"].as_str().unwrap_or(""));
        let light = row["light"].as_str().unwrap_or("");
        let (_, _, moving, fixed) = paper.iter().find(|p| (p.0, p.1.as_str()) == key).expect("a paper row");
        let expected = if light == "fixed" { *fixed } else { *moving };
        assert_eq!(row["paper_fps"].as_f64(), Some(expected), "{row}");
    }
    let markdown = std::fs::read_to_string(out.join("table1.md")).expect("table1.md");
    for (_, _, moving, fixed) in &paper {
        for value in [moving, fixed] {
            assert!(markdown.contains(&format!("{value:.2}")), "paper value {value} missing:\n{markdown}");
        }
    }
    assert_eq!(markdown.lines().filter(|l| l.starts_with("| atlas-")).count(), 8 + 8, "{markdown}");

    // A fixed light skips the shadow map (and bake): faster than a moving one, per round of the
    // same run, for both techniques on both scenes.
    let ratios = json["ratios"].as_array().expect("ratios");
    assert_eq!(ratios.len(), 8, "{json}");
    let fixed_over_moving: Vec<_> =
        ratios.iter().filter(|r| r["compared"].as_str().is_some_and(|c| c.contains("fixed / moving"))).collect();
    assert_eq!(fixed_over_moving.len(), 4, "{json}");
    for ratio in fixed_over_moving {
        let measured = ratio["measured"]["median"].as_f64().expect("measured ratio");
        println!("{} {}: {measured:.2} (paper {})", ratio["scene"], ratio["compared"], ratio["paper"]);
        assert!(measured > 1.0, "fixed light not faster than moving: {ratio}");
    }
    let refused = common::run_err(&["bench", "--technique", "planar", "--table1-out", out.to_str().unwrap()]);
    assert!(refused.contains("--table1-out") && refused.contains("planar"), "{refused}");
}

/// The paper's Table 1 as (scene, technique as JSON spells it, moving light fps, fixed light fps).
fn shadow_atlas_paper_values() -> Vec<(&'static str, String, f64, f64)> {
    let spelt = |k: &ShadowKind| serde_json::to_value(k).ok().and_then(|v| v.as_str().map(str::to_owned));
    nostencil::profile::table1::PAPER_TABLE1
        .iter()
        .map(|(s, k, m, f)| (*s, spelt(k).expect("technique as JSON"), *m, *f))
        .collect()
}

#[test]
fn atlas_125_models_are_shadowed_where_a_cpu_ray_cast_says() {
    let gpu = common::gpu();
    let scene = builtin_scene("atlas-125").expect("scene");
    let baked = bake(&gpu, &scene, ShadowAtlasOptions::default());
    let Light::Directional { direction } = scene.light() else { panic!("atlas-125 has a directional light") };
    let to_light = -direction.normalize();
    let radius = horned_radius(&nostencil::scene::builtin::ATLAS_HORNS);
    // Which shadow-casting object (if any) a ray from `origin` towards the light hits first-found.
    let world = RayWorld::of(&scene);
    let occluder = |origin: Vec3| world.occluder(origin, to_light);
    // The bake can only be as sharp as the shadow map it reads: one map texel spans 2 scene
    // radii / 512 (about 0.05 here), a texel of a model's 64x64 shadow texture about as much, so
    // a texel is checked only where the answer holds 2 texels (2 map texels, 2 PCF taps) away.
    const REACH: i32 = 2;
    let (centre_radius, map_size) = (shadow_atlas::scene_bounds(&scene).1, ShadowAtlasOptions::default().map_size);
    println!("shadow map texel: {:.3} world units", 2.0 * centre_radius / map_size as f32);
    let (mut checked_models, mut lit, mut shadowed, mut by_others) = (0, 0, 0, 0);
    let mut wrong = Vec::new();
    for (index, object) in scene.objects.iter().enumerate().filter(|(_, o)| o.name.starts_with("model")) {
        let texture = baked.read_shadow_texture(index, 0).expect("read back");
        assert_eq!(texture.dimensions(), (64, 64), "{}", object.name);
        let normal_matrix = object.transform.inverse().transpose();
        // The surface at a texel centre, in world space, with its outward normal.
        let surface = |x: f32, y: f32| {
            let at = |u: f32, v: f32| {
                let d = octahedral_direction(u / 64.0 * 2.0 - 1.0, v / 64.0 * 2.0 - 1.0);
                d * radius(d)
            };
            let p = at(x, y);
            let mut n = (at(x + 0.5, y) - at(x - 0.5, y)).cross(at(x, y + 0.5) - at(x, y - 0.5)).normalize_or_zero();
            if n.dot(p) < 0.0 {
                n = -n;
            }
            (object.transform.transform_point3(p), normal_matrix.transform_vector3(n).normalize_or_zero())
        };
        // None: facing away or grazing (not a test of occlusion; below N.L 0.4 the 2-texel
        // reach would shrink under a map texel seen from the light); else the occluding object.
        let answer = |x: f32, y: f32| -> Option<Option<usize>> {
            let (p, n) = surface(x, y);
            (n.dot(to_light) >= 0.4).then(|| occluder(p + n * 0.008))
        };
        let mut any = false;
        for y in (3..61u32).step_by(5) {
            for x in (3..61u32).step_by(5) {
                let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                let Some(here) = answer(cx, cy) else { continue };
                // Robust texels only: the same answer 2 texels away all round (no shadow edge
                // nearby; see `reach` above).
                let robust = (-1..=1).all(|dy| {
                    (-1..=1).all(|dx| {
                        let (nx, ny) = (cx + (dx * REACH) as f32, cy + (dy * REACH) as f32);
                        answer(nx, ny).map(|a| a.is_some()) == Some(here.is_some())
                    })
                });
                if !robust {
                    continue;
                }
                any = true;
                let value = texture.get_pixel(x, y).0[0];
                match here {
                    None => {
                        lit += 1;
                        if value <= 200 {
                            wrong.push(format!(
                                "{} texel ({x}, {y}) baked {value}, the ray reaches the light",
                                object.name
                            ));
                        }
                    }
                    Some(by) => {
                        shadowed += 1;
                        by_others += (by != index) as u32;
                        let other = &scene.objects[by].name;
                        if value >= 55 {
                            wrong.push(format!("{} texel ({x}, {y}) baked {value}, the ray hits {other}", object.name));
                        }
                    }
                }
            }
        }
        checked_models += any as u32;
    }
    println!("atlas-125: {checked_models} models checked: {lit} lit texels, {shadowed} shadowed ({by_others} by another model)");
    assert!(wrong.is_empty(), "{} wrong texels:\n{}", wrong.len(), wrong.join("\n"));
    assert_eq!(checked_models, 125);
    assert!(lit > 1000 && shadowed > 400 && by_others > 300, "{lit} lit, {shadowed} shadowed, {by_others} by others");
    common::assert_no_validation_messages(&gpu);
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

#[test]
fn ray_world_answers_as_every_triangle_does() {
    let scene = builtin_scene("atlas-one").expect("scene");
    let world = RayWorld::of(&scene);
    let triangles = world_triangles(&scene);
    let nearest = |origin: Vec3, dir: Vec3| {
        triangles
            .iter()
            .filter_map(|(i, t)| ray_hits_triangle(origin, dir, *t).map(|d| (*i, d)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    };
    let Light::Directional { direction } = scene.light() else { panic!("atlas-one has a directional light") };
    let inverse = scene.camera.view_projection(1.0).inverse();
    let eye = scene.camera.eye;
    let (mut hits, mut occluded) = (0, 0);
    for i in 0..400u32 {
        // A 20x20 grid over the frame, the rays through it and from their hits to the light.
        let ndc = Vec3::new((i % 20) as f32 / 10.0 - 0.95, (i / 20) as f32 / 10.0 - 0.95, 0.5);
        let dir = (inverse.project_point3(ndc) - eye).normalize();
        let expected = nearest(eye, dir);
        let hit = world.first_hit(eye, dir);
        assert_eq!(hit.map(|h| h.object), expected.map(|e| e.0), "ray {i}");
        let (Some(hit), Some((_, distance))) = (hit, expected) else { continue };
        assert!((hit.distance - distance).abs() < 1e-5, "ray {i}: {} against {distance}", hit.distance);
        hits += 1;
        let origin = eye + dir * distance * 0.999;
        let blocked = triangles.iter().any(|(o, t)| {
            scene.objects[*o].casts_shadow && ray_hits_triangle(origin, -direction, *t).is_some_and(|d| d > 1e-4)
        });
        assert_eq!(world.occluder(origin, -direction).is_some(), blocked, "shadow ray {i}");
        occluded += blocked as u32;
    }
    println!("{hits} of 400 camera rays hit, {occluded} of them in shadow");
    assert!(hits > 200 && occluded > 20, "{hits} hits, {occluded} occluded");
}

/// What the CPU finds through one pixel of a frame: the nearest surface and whether the light
/// reaches it.
#[derive(Clone, Copy)]
struct Seen {
    object: usize,
    point: Vec3,
    /// The vertex normals interpolated at the point, as the shaders get them.
    normal: Vec3,
    n_dot_l: f32,
    /// A shadow caster between the point and the light (searched only where N.L > 0).
    occluder: Option<usize>,
    /// World length of one texel of the object's shadow texture (the longest along the hit
    /// triangle's edges).
    texel: f32,
}

impl Seen {
    fn lit(&self) -> bool {
        self.n_dot_l > 0.0 && self.occluder.is_none()
    }
}

/// Barycentric weights of `p` (in the triangle's plane) in triangle `t`.
fn barycentric(t: [Vec3; 3], p: Vec3) -> [f32; 3] {
    let (e1, e2, d) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let det = d11 * d22 - d12 * d12;
    let (v, w) = ((d22 * d1 - d12 * d2) / det, (d11 * d2 - d12 * d1) / det);
    [1.0 - v - w, v, w]
}

/// The CPU's answer for a frame of atlas-125 under a directional light: camera rays through
/// the frame's pixels, the surfaces they meet, and whether the light reaches those surfaces.
struct CpuFrame<'s> {
    scene: &'s Scene,
    world: RayWorld,
    size: (u32, u32),
    /// The frame uniforms' matrix (y down the framebuffer: the projection flips it for Vulkan).
    view_projection: Mat4,
    to_light: Vec3,
    /// Side of each mesh's shadow texture, as the renderer laid its atlas out.
    texture_sizes: Vec<u32>,
    ground: usize,
    /// World size of one shadow-map texel: 2 scene radii / map size.
    map_texel: f32,
}

impl CpuFrame<'_> {
    /// How far a shadow ray starts off the surface, along the normal (as in the texel test).
    const OFFSET: f32 = 0.008;

    /// The unit camera ray through framebuffer point (fx, fy) (pixel centres at + 0.5).
    fn ray(&self, fx: f32, fy: f32) -> Vec3 {
        let (w, h) = (self.size.0 as f32, self.size.1 as f32);
        let ndc = Vec3::new(fx / w * 2.0 - 1.0, fy / h * 2.0 - 1.0, 0.5);
        (self.view_projection.inverse().project_point3(ndc) - self.scene.camera.eye).normalize()
    }

    /// A shadow caster between surface point `p` (normal `n`) and the light (N.L aside).
    fn occluder(&self, p: Vec3, n: Vec3) -> Option<usize> {
        self.world.occluder(p + n * Self::OFFSET, self.to_light)
    }

    fn seen(&self, x: u32, y: u32) -> Option<Seen> {
        let eye = self.scene.camera.eye;
        let dir = self.ray(x as f32 + 0.5, y as f32 + 0.5);
        let hit = self.world.first_hit(eye, dir)?;
        let object = &self.scene.objects[hit.object];
        let mesh = &self.scene.meshes[object.mesh].data;
        let corners = [0, 1, 2].map(|k| mesh.indices[hit.triangle * 3 + k] as usize);
        let placed = corners.map(|v| object.transform.transform_point3(mesh.positions[v]));
        let point = eye + dir * hit.distance;
        let weights = barycentric(placed, point);
        let interpolated: Vec3 = (0..3).map(|k| mesh.normals[corners[k]] * weights[k]).sum();
        let normal = object.transform.inverse().transpose().transform_vector3(interpolated).normalize();
        let n_dot_l = normal.dot(self.to_light);
        let occluder = if n_dot_l > 0.0 { self.occluder(point, normal) } else { None };
        let size = self.texture_sizes[object.mesh] as f32;
        let texel = (0..3)
            .map(|k| {
                let (a, b) = (corners[k], corners[(k + 1) % 3]);
                (placed[(k + 1) % 3] - placed[k]).length() / ((mesh.uvs[b] - mesh.uvs[a]).length() * size).max(1e-6)
            })
            .fold(0.0, f32::max);
        Some(Seen { object: hit.object, point, normal, n_dot_l, occluder, texel })
    }

    /// The surface of object `index` near `q`, with its outward normal: a model's horned sphere
    /// along its radius (the shape its 64x64 grid samples), the ground straight below.
    fn surface_near(&self, index: usize, q: Vec3) -> (Vec3, Vec3) {
        if index == self.ground {
            return (Vec3::new(q.x, 0.0, q.z), Vec3::Y);
        }
        let radius = horned_radius(&nostencil::scene::builtin::ATLAS_HORNS);
        let transform = self.scene.objects[index].transform;
        let d = transform.inverse().transform_point3(q).normalize();
        let shape = |d: Vec3| d * radius(d);
        let (t1, t2) = d.any_orthonormal_pair();
        let across = |t: Vec3| shape((d + t * 1e-3).normalize()) - shape((d - t * 1e-3).normalize());
        let n = across(t1).cross(across(t2));
        let n = if n.dot(d) < 0.0 { -n } else { n };
        (transform.transform_point3(shape(d)), transform.inverse().transpose().transform_vector3(n).normalize())
    }

    /// The world length one pixel step spans on the plane of `s` (seen through pixel (x, y)):
    /// the footprint by which the frame picks the shadow texture's mip.
    fn footprint(&self, s: &Seen, x: u32, y: u32) -> f32 {
        let eye = self.scene.camera.eye;
        let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
        [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)]
            .iter()
            .map(|(dx, dy)| {
                let dir = self.ray(cx + dx, cy + dy);
                let t = (s.point - eye).dot(s.normal) / dir.dot(s.normal);
                (eye + dir * t - s.point).length()
            })
            .fold(0.0, f32::max)
    }

    /// Whether every surface point within `reach` of `s` (sampled every half map texel, so
    /// that no gap the map resolves is missed) faces the light by N.L >= 0.2 (clear of the
    /// terminator and the bias) and gets the same answer as `s`.
    fn holds_around(&self, s: &Seen, reach: f32) -> bool {
        let (t1, t2) = s.normal.any_orthonormal_pair();
        let step = 0.5 * self.map_texel;
        let n = (reach / step).ceil() as i32;
        (-n..=n)
            .flat_map(|i| (-n..=n).map(move |j| (t1 * i as f32 + t2 * j as f32) * step))
            .filter(|offset| offset.length() <= reach)
            .all(|offset| {
                let (p, n) = self.surface_near(s.object, s.point + offset);
                n.dot(self.to_light) >= 0.2 && self.occluder(p, n).is_none() == s.lit()
            })
    }

    /// Whether the frame's pixel over `s` must show exactly lit or exactly shadowed: N.L >= 0.4
    /// (lit and shadowed differ clearly), every pixel within 2 sees the same object with the
    /// same answer, and the answer holds as far as the frame's shadow edges can blur. The bake
    /// compares texel centres against the shadow map with 2x2 PCF (2 texels of the coarser of
    /// map and shadow texture); the frame samples the shadow texture trilinearly at the pixel's
    /// footprint, from mip texels at most 2 footprints wide (2 more footprints).
    fn robust(&self, seen: &[Option<Seen>], x: u32, y: u32) -> bool {
        let (w, h) = (self.size.0 as i32, self.size.1 as i32);
        let at = |x: i32, y: i32| (x >= 0 && y >= 0 && x < w && y < h).then(|| seen[(y * w + x) as usize]).flatten();
        let Some(here) = at(x as i32, y as i32) else { return false };
        let same = |s: Option<Seen>| s.is_some_and(|s| s.object == here.object && s.lit() == here.lit());
        here.n_dot_l >= 0.4
            && (-2..=2).all(|dy| (-2..=2).all(|dx| same(at(x as i32 + dx, y as i32 + dy))))
            && self.holds_around(&here, 2.0 * self.map_texel.max(here.texel) + 2.0 * self.footprint(&here, x, y))
    }
}

/// The atlas-125 frame of `shadow-texture-atlas`, pixel by pixel on a grid of every 3rd pixel,
/// where a CPU ray cast decides the shadow beyond doubt: the pixel must be the `lit`
/// technique's pixel where the light reaches the surface, and base colour x ambient where it
/// does not.
#[test]
fn atlas_125_frame_is_shadowed_where_a_cpu_ray_cast_says() {
    let gpu = common::gpu();
    let scene = builtin_scene("atlas-125").expect("scene");
    let (w, h) = (256u32, 256u32);
    let options = RenderOptions {
        width: w,
        height: h,
        stencil: StencilMode::Emulated,
        technique: technique("shadow-texture-atlas"),
        ..Default::default()
    };
    let frame = render_scene(&gpu, &scene, &options).expect("atlas frame");
    let atlases = frame.stats::<ShadowAtlasStats>().expect("atlas stats").atlases.clone();
    let atlas = frame.output.image;
    let lit_frame = render_scene(&gpu, &scene, &options.with_technique(technique("lit"))).expect("lit").output.image;
    // The technique has no stencil to emulate: the reference path must draw the same frame.
    let reference = RenderOptions { stencil: StencilMode::Reference, ..options.clone() };
    let reference = render_scene(&gpu, &scene, &reference).expect("reference frame").output.image;
    let differing = atlas.pixels().zip(reference.pixels()).filter(|(p, q)| p.0[..3] != q.0[..3]).count();
    assert_eq!(differing, 0, "emulated and reference stencil frames differ in {differing} pixels");

    // The atlas UVs the CPU reads are the meshes' own: the models' grid coordinates, the
    // ground's TEXCOORD_0 (the plane y = 0).
    let ground = scene.objects.iter().position(|o| o.name == "ground").expect("the ground");
    assert_eq!(scene.objects[ground].transform, Mat4::IDENTITY);
    for (index, object) in scene.objects.iter().enumerate() {
        let source = atlases[object.mesh].source;
        let expected = if index == ground { AtlasSource::TexCoord0 } else { AtlasSource::GeometryImage { n: 64 } };
        assert_eq!(source, expected, "{}", object.name);
    }
    let Light::Directional { direction } = scene.light() else { panic!("atlas-125 has a directional light") };
    let cpu = CpuFrame {
        scene: &scene,
        world: RayWorld::of(&scene),
        size: (w, h),
        view_projection: scene.camera.view_projection(w as f32 / h as f32),
        to_light: -direction.normalize(),
        texture_sizes: atlases.iter().map(|a| a.size).collect(),
        ground,
        map_texel: 2.0 * shadow_atlas::scene_bounds(&scene).1 / options.shadow_atlas.map_size as f32,
    };
    let seen: Vec<Option<Seen>> = (0..w * h).map(|i| cpu.seen(i % w, i / w)).collect();
    // The rays are the frame's: every hit projects back onto its pixel centre.
    let mut worst = 0f32;
    for (i, s) in seen.iter().enumerate() {
        let Some(s) = s else { continue };
        let clip = cpu.view_projection * s.point.extend(1.0);
        let x = (clip.x / clip.w + 1.0) * 0.5 * w as f32;
        let y = common::pixel_y(&scene, s.point, (w, h));
        worst = worst.max((x - (i as u32 % w) as f32 - 0.5).abs()).max((y - (i as u32 / w) as f32 - 0.5).abs());
    }
    assert!(worst < 0.01, "a hit point projects {worst} px away from its pixel centre");

    // For a person to look at: the frame in grey, checked pixels green (lit), blue (shadowed)
    // or red (wrong).
    let mut mask = RgbaImage::from_fn(w, h, |x, y| {
        let p = atlas.get_pixel(x, y).0;
        let grey = ((p[0] as u32 + p[1] as u32 + p[2] as u32) / 6) as u8;
        image::Rgba([grey, grey, grey, 255])
    });
    let (mut lit, mut shadowed, mut by_others, mut shadowed_models, mut on_ground) = (0u32, 0u32, 0u32, 0u32, 0u32);
    let (mut worst_lit, mut worst_lambert, mut worst_shadowed) = (0u8, 0u8, 0u8);
    let mut wrong = Vec::new();
    let differs = |a: &[u8], b: &[u8]| (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
    for (x, y) in (2..h - 2).step_by(3).flat_map(|y| (2..w - 2).step_by(3).map(move |x| (x, y))) {
        let Some(here) = seen[(y * w + x) as usize].filter(|_| cpu.robust(&seen, x, y)) else { continue };
        let object = &scene.objects[here.object];
        let base = scene.base_colour(object);
        let (got, unshadowed) = (atlas.get_pixel(x, y).0, lit_frame.get_pixel(x, y).0);
        on_ground += (here.object == ground) as u32;
        let expected = if here.lit() {
            lit += 1;
            // Visibility 1: the atlas shader's light term is the lit shader's (ambient +
            // (1 - ambient) N.L), but for the two pipelines' float rounding; the lit frame is
            // that Lambert term too, by the CPU's interpolated normal.
            let lambert = common::srgb8(base * (scene.ambient + (1.0 - scene.ambient) * here.n_dot_l));
            worst_lambert = worst_lambert.max(differs(&unshadowed, &lambert));
            unshadowed[..3].to_vec()
        } else {
            shadowed += 1;
            by_others += (here.occluder != Some(here.object)) as u32;
            shadowed_models += (here.object != ground) as u32;
            // Visibility 0 leaves the ambient term alone: base colour x ambient, whatever the
            // normal, and clearly darker than the lit frame (N.L >= 0.4).
            common::srgb8(base * scene.ambient).to_vec()
        };
        let off = differs(&got, &expected);
        if here.lit() {
            worst_lit = worst_lit.max(off);
        } else {
            worst_shadowed = worst_shadowed.max(off);
        }
        // Float rounding of two pipelines (measured: 0 lit, 1 shadowed). A visibility of 2%
        // (5 of 255 in the shadow texture) on the shadowed ground would be 3 off.
        let bad = off > 2;
        if bad {
            let occluder = here.occluder.map_or("nothing", |o| scene.objects[o].name.as_str());
            wrong.push(format!(
                "pixel ({x}, {y}) on {}: {:?}, expected {expected:?} (the ray to the light hits {occluder})",
                object.name,
                &got[..3]
            ));
        }
        let colour = match (bad, here.lit()) {
            (true, _) => [255, 0, 0, 255],
            (false, true) => [0, 255, 0, 255],
            (false, false) => [0, 96, 255, 255],
        };
        mask.put_pixel(x, y, image::Rgba(colour));
    }
    let dir = common::scratch_dir("atlas-125-frame");
    for (image, name) in [(&atlas, "atlas"), (&lit_frame, "lit"), (&mask, "checked")] {
        nostencil::write_png(image, &dir.join(format!("{name}.png")), false).expect("write png");
    }
    let on_models = lit + shadowed - on_ground;
    println!(
        "atlas-125 frame {w}x{h}: {lit} lit pixels checked (largest difference from the lit frame {worst_lit}, \
         the lit frame's from the CPU's Lambert {worst_lambert}), {shadowed} shadowed ({by_others} by another \
         model, {shadowed_models} on models; largest difference from base x ambient {worst_shadowed}); \
         {on_ground} on the ground, {on_models} on models; map texel {:.3}; checked pixels drawn in {}",
        cpu.map_texel,
        dir.join("checked.png").display()
    );
    assert!(wrong.is_empty(), "{} wrong pixels:\n{}", wrong.len(), wrong.join("\n"));
    assert!(worst_lambert <= 2, "the lit frame is {worst_lambert} off the CPU's Lambert term");
    // The counts depend on the CPU alone (measured 1,457 lit, 191 shadowed, all by another
    // model, 16 of them on models; 1,403 on the ground, 245 on models).
    assert!(
        lit >= 1200 && shadowed >= 150 && by_others >= 150,
        "{lit} lit, {shadowed} shadowed, {by_others} by others"
    );
    assert!(
        on_ground >= 1200 && on_models >= 200 && shadowed_models >= 12,
        "{on_ground} on the ground, {on_models} on models, {shadowed_models} of them shadowed"
    );
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn mip_flicker_counts_flickering_pixels_of_both_techniques() {
    // atlas-one minified to 96x72: the model covers a few hundred pixels and its 256x256 shadow
    // texture is sampled around mip 3, where the map's compare still snaps per pixel.
    let args =
        "bench --technique shadow-texture-atlas --scene atlas-one --size 96x72 --mip-flicker 12 --json --validation";
    let (out, err) = common::run_ok(&args.split(' ').collect::<Vec<_>>());
    assert!(!err.contains("vulkan validation"), "{err}");
    let report: serde_json::Value = serde_json::from_str(&out).expect("--mip-flicker --json is JSON");
    assert_eq!(report["schema"], "nostencil-mip-flicker/1");
    assert_eq!((report["steps"].as_u64(), report["width"].as_u64()), (Some(12), Some(96)), "{report}");
    let rows = report["rows"].as_array().expect("rows");
    let techniques: Vec<&str> = rows.iter().filter_map(|r| r["technique"].as_str()).collect();
    assert_eq!(techniques, ["atlas", "map"], "{report}");
    let count = |row: &serde_json::Value, key: &str| row[key].as_u64().expect(key);
    for row in rows {
        let (pixels, events) = (count(row, "flickering_pixels"), count(row, "flicker_events"));
        assert!(pixels <= 96 * 72 && pixels <= events && events <= 12 * pixels, "{row}");
        assert!(row["mean_change"].as_f64().is_some_and(|m| m > 0.0 && m < 32.0), "{row}");
    }
    let (atlas, map) = (count(&rows[0], "flickering_pixels"), count(&rows[1], "flickering_pixels"));
    println!("flickering pixels at 96x72 over 12 steps: shadow texture {atlas}, shadow map {map}");
    // The shadow map's edge snaps from pixel to pixel as the light turns: it must flicker
    // somewhere, or the measurement measures nothing.
    assert!(map >= 20, "{report}");
    // The paper's claim, which holds by a wide margin at this size (0 against 109 on lavapipe).
    assert!(atlas * 4 < map, "mips did not reduce the flicker: {atlas} against {map}");

    let refused = common::run_err(&["bench", "--technique", "planar", "--mip-flicker"]);
    assert!(refused.contains("--mip-flicker") && refused.contains("planar"), "{refused}");
    let refused = common::run_err(&["bench", "--mip-flicker", "--each-extrusion"]);
    assert!(refused.contains("--mip-flicker is not timed") && refused.contains("--each-extrusion"), "{refused}");
}

#[test]
fn projective_texture_shadows_lit_parts_of_a_concave_model_that_the_atlas_leaves_lit() {
    // The paper's figure 2: a texel of a texture projected from the light stands for every
    // surface on its light ray, so the lit horn in front of the body's self-shadow takes it.
    let gpu = common::gpu();
    let scene = builtin_scene("atlas-one").expect("scene");
    let (w, h) = (160u32, 120u32);
    let projective = render(&gpu, &scene, technique("projective-texture"), (w, h));
    let atlas = render(&gpu, &scene, technique("shadow-texture-atlas"), (w, h));
    let dir = common::scratch_dir("projective-vs-atlas");
    for (image, name) in [(&projective, "projective-texture"), (&atlas, "atlas")] {
        nostencil::write_png(image, &dir.join(format!("{name}.png")), false).expect("write png");
    }
    // Pixels the projective texture leaves clearly darker than the atlas.
    let darker: Vec<(u32, u32)> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (p, a) = (projective.get_pixel(x, y).0, atlas.get_pixel(x, y).0);
            (0..3).all(|c| a[c] >= p[c]) && (0..3).any(|c| a[c] > p[c].saturating_add(24))
        })
        .collect();

    // CPU answer for a pixel: the nearest surface on its camera ray and whether a ray from
    // there reaches the light (None: not a light-facing point of the model).
    let Light::Directional { direction } = scene.light() else { panic!("atlas-one has a directional light") };
    let to_light = -direction.normalize();
    let triangles = world_triangles(&scene);
    let model = scene.objects.iter().position(|o| o.name == "model").expect("the model");
    let inverse = scene.camera.view_projection(w as f32 / h as f32).inverse();
    let lit_model_point = |x: u32, y: u32| -> Option<bool> {
        let ndc = Vec2::new((x as f32 + 0.5) / w as f32 * 2.0 - 1.0, (y as f32 + 0.5) / h as f32 * 2.0 - 1.0);
        let eye = scene.camera.eye;
        let ray = (inverse.project_point3(ndc.extend(0.5)) - eye).normalize();
        let (object, t, d) = triangles
            .iter()
            .filter_map(|(i, t)| ray_hits_triangle(eye, ray, *t).map(|d| (*i, *t, d)))
            .min_by(|a, b| a.2.total_cmp(&b.2))?;
        let mut n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero();
        if n.dot(ray) > 0.0 {
            n = -n;
        }
        if object != model || n.dot(to_light) < 0.3 {
            return None;
        }
        let origin = eye + ray * d + n * 0.01;
        Some(!triangles.iter().any(|(_, t)| ray_hits_triangle(origin, to_light, *t).is_some_and(|d| d > 1e-4)))
    };
    let sampled: Vec<(u32, u32)> = darker.iter().step_by((darker.len() / 60).max(1)).copied().collect();
    let answers: Vec<Option<bool>> = sampled.iter().map(|&(x, y)| lit_model_point(x, y)).collect();
    let lit = answers.iter().filter(|a| **a == Some(true)).count();
    let occluded = answers.iter().filter(|a| **a == Some(false)).count();
    println!(
        "{} pixels darker under the projective texture than the atlas; of {} sampled, {lit} are light-facing \
         points of the model that a ray cast finds lit, {occluded} in shadow",
        darker.len(),
        sampled.len()
    );
    assert!(darker.len() >= 40, "the projective texture must show its flaw: {} pixels", darker.len());
    assert!(lit * 2 >= sampled.len(), "{lit} of {} sampled pixels are lit model surface", sampled.len());
    assert!(occluded * 10 <= sampled.len(), "{occluded} of them are really in shadow");
    common::assert_no_validation_messages(&gpu);
}
