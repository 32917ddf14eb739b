//! What the loader reads beyond core glTF, checked on the shared real files (blender/*,
//! gltf-transform/*) and on files derived from BoxTextured.glb: material extensions and texture
//! transforms into `Model`, EXT_meshopt_compression, buffers loaded only when used, and the valid
//! JSON forms gltf-json alone would refuse.

use std::path::Path;

use glam::{Vec2, Vec3, Vec4};
use serde_json::{json, Value};

use super::load_gltf;
use super::tests::{assert_mentions, assets, glb_parts, load, load_error, make_glb, TempDir};
use crate::scene::model::{AlphaMode, Model, TextureTransform};

/// Every .gltf and .glb under `dir`, sorted.
fn gltf_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            gltf_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "gltf" || e == "glb") {
            out.push(path);
        }
    }
}

#[test]
fn every_test_asset_loads() {
    let mut files = Vec::new();
    gltf_files(&assets(), &mut files);
    assert!(files.len() >= 15, "{} files", files.len());
    for path in &files {
        let model = load_gltf(path).unwrap_or_else(|e| panic!("{e}"));
        let triangles: usize = model.meshes.iter().flat_map(|m| &m.primitives).map(|p| p.triangle_count()).sum();
        assert!(triangles > 0, "{}: no triangles", path.display());
        for w in &model.warnings {
            eprintln!("{}: warning: {w}", path.display());
        }
    }
}

fn near2(a: Vec2, b: Vec2) -> bool {
    (a - b).abs().max_element() < 1e-6
}

#[test]
fn texture_transforms_of_base_colour_and_emissive_are_read() {
    let model = load(&assets(), "blender/09_texture_transform/09_texture_transform.gltf");
    let m = &model.materials[0];
    let base = m.base_color_texture.expect("base colour texture");
    let t = base.transform.expect("base colour transform");
    assert!(near2(t.offset, Vec2::new(0.1, 0.2)) && (t.rotation - 0.3).abs() < 1e-6, "{t:?}");
    assert!(near2(t.scale, Vec2::new(4.0, 5.0)), "{t:?}");
    assert_eq!(base.tex_coord, 0);
    let emissive = m.emissive_texture.expect("emissive texture");
    let t = emissive.transform.expect("emissive transform");
    assert!(near2(t.offset, Vec2::new(0.5, 0.6)) && (t.rotation - 0.7).abs() < 1e-6, "{t:?}");
    assert!(near2(t.scale, Vec2::new(8.0, 9.0)), "{t:?}");
    // One glTF texture, decoded once, sRGB for both uses.
    assert_eq!(base.texture, emissive.texture);
    assert_eq!(model.textures.len(), 1);
    assert!(model.textures[0].srgb);
    // The matrix is the extension's T * R * S: (1, 0) goes to offset + R(scale.x, 0).
    let p = t.matrix() * Vec3::new(1.0, 0.0, 1.0);
    let (s, c) = 0.7f32.sin_cos();
    assert!(near2(p.truncate(), Vec2::new(0.5 + 8.0 * c, 0.6 - 8.0 * s)), "{p}");
}

#[test]
fn unlit_mask_and_vertex_colours_are_read() {
    let dir = assets();
    let unlit = load(&dir, "blender/01_unlit/01_unlit.gltf");
    assert_eq!(unlit.materials.len(), 2);
    assert!(unlit.materials.iter().all(|m| m.unlit));
    assert_eq!(unlit.materials[1].alpha_mode, AlphaMode::Blend);
    assert!((unlit.materials[1].base_color - Vec4::new(0.0, 0.217_637_64, 1.0, 0.5)).abs().max_element() < 1e-6);
    assert!(unlit.warnings.is_empty(), "{:?}", unlit.warnings);

    let mask = load(&dir, "blender/01_alpha_mask/01_alpha_mask.gltf");
    let m = &mask.materials[0];
    assert_eq!(m.alpha_mode, AlphaMode::Mask { cutoff: 0.42 });
    assert!(m.double_sided && !m.unlit);
    assert!(m.base_color_texture.is_some_and(|t| t.transform.is_none() && t.tex_coord == 0));

    for name in ["blender/01_color_attribute/01_color_attribute.gltf", "gltf-transform/BoxVertexColors.glb"] {
        let model = load(&dir, name);
        let prim = &model.meshes[0].primitives[0];
        let colours = prim.colors.as_ref().unwrap_or_else(|| panic!("{name}: no COLOR_0"));
        assert_eq!(colours.len(), prim.positions.len());
        assert!(colours.iter().all(|c| c.cmpge(Vec4::ZERO).all() && c.cmple(Vec4::ONE).all()), "{name}");
        assert!(colours.iter().any(|c| *c != colours[0]), "{name}: one colour only");
    }
}

#[test]
fn specular_glossiness_diffuse_becomes_the_base_colour() {
    let sphere = load(&assets(), "blender/04_sphere_specular_glossiness/04_sphere_specular_glossiness.gltf");
    // diffuseFactor absent: its default, white.
    assert_eq!(sphere.materials[0].base_color, Vec4::ONE);

    // Diffuse factor and texture win over a metallic-roughness fallback.
    let (mut json, bin) = textured();
    let material = &mut json["materials"][0];
    material["pbrMetallicRoughness"] = json!({"baseColorFactor": [0.1, 0.1, 0.1, 1.0]});
    material["extensions"] = json!({"KHR_materials_pbrSpecularGlossiness": {
        "diffuseFactor": [0.2, 0.4, 0.6, 0.8],
        "diffuseTexture": {"index": 0, "extensions": {"KHR_texture_transform": {"scale": [2, 3], "texCoord": 1}}}
    }});
    json["extensionsUsed"] = json!(["KHR_materials_pbrSpecularGlossiness", "KHR_texture_transform"]);
    json["extensionsRequired"] = json["extensionsUsed"].clone();
    let model = load_derived("SpecGloss.glb", &json, &bin);
    let m = &model.materials[0];
    assert_eq!(m.base_color, Vec4::new(0.2, 0.4, 0.6, 0.8));
    let texture = m.base_color_texture.expect("diffuse texture");
    // The transform's texCoord overrides the textureInfo's.
    assert_eq!(texture.tex_coord, 1);
    assert_eq!(
        texture.transform,
        Some(TextureTransform { offset: Vec2::ZERO, rotation: 0.0, scale: Vec2::new(2.0, 3.0) })
    );
    // The box has no TEXCOORD_1: said once, for the one primitive.
    assert_eq!(model.warnings.len(), 1, "{:?}", model.warnings);
    assert_mentions(&model.warnings[0], &["primitive 0", "base colour texture reads TEXCOORD_1"]);
}

/// BoxTextured.glb as JSON and BIN.
fn textured() -> (Value, Vec<u8>) {
    glb_parts(&std::fs::read(assets().join("BoxTextured.glb")).unwrap())
}

fn load_derived(name: &str, json: &Value, bin: &[u8]) -> Model {
    let tmp = TempDir::new(&format!("ext-{name}"));
    let path = tmp.write(name, &make_glb(json, bin));
    load_gltf(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn textures_without_a_decodable_source_leave_the_factor_with_a_warning() {
    let (mut json, bin) = textured();
    json["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = json!([0.5, 0.25, 1.0, 1.0]);
    json["textures"] = json!([{"sampler": 0}]);
    let model = load_derived("NoSource.glb", &json, &bin);
    assert!(model.materials[0].base_color_texture.is_none());
    assert_eq!(model.materials[0].base_color, Vec4::new(0.5, 0.25, 1.0, 1.0));
    let warning = model.warnings.iter().find(|w| w.contains("texture 0")).expect("a warning");
    assert_mentions(warning, &["material 0 'Texture'", "no `source`"]);

    json["textures"] = json!([{"extensions": {"KHR_texture_basisu": {"source": 0}}}]);
    json["extensionsUsed"] = json!(["KHR_texture_basisu"]);
    json["extensionsRequired"] = json!(["KHR_texture_basisu"]);
    let tmp = TempDir::new("basisu-required");
    // Required, it changes what the image is: refused by name.
    let msg = load_error(&tmp, "Basisu.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["requires extension KHR_texture_basisu"]);
    json.as_object_mut().unwrap().remove("extensionsRequired");
    let model = load_derived("Basisu.glb", &json, &bin);
    let warning = model.warnings.iter().find(|w| w.contains("texture 0")).expect("a warning");
    assert_mentions(warning, &["material 0 'Texture'", "KHR_texture_basisu", "not decoded"]);
}

#[test]
fn emissive_textures_unlit_transmission_and_variants() {
    let (mut json, bin) = textured();
    let base = json["materials"][0].clone();
    let mut second = base.clone();
    second["name"] = json!("Glass");
    second["emissiveFactor"] = json!([1.0, 0.5, 0.25]);
    second["emissiveTexture"] = json!({"index": 0, "texCoord": 1});
    second["extensions"] =
        json!({"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_unlit": {}});
    let mut third = base.clone();
    third["extensions"] = json!({"KHR_materials_transmission": {}});
    json["materials"] = json!([base, second, third]);
    json["meshes"][0]["primitives"][0]["extensions"] =
        json!({"KHR_materials_variants": {"mappings": [{"material": 1, "variants": [0]}]}});
    json["extensions"] = json!({"KHR_materials_variants": {"variants": [{"name": "glass"}]}});
    let used = ["KHR_materials_transmission", "KHR_materials_unlit", "KHR_materials_variants"];
    json["extensionsUsed"] = json!(used);
    json["extensionsRequired"] = json!(used);
    let model = load_derived("Materials.glb", &json, &bin);
    let glass = &model.materials[1];
    assert!(glass.unlit && !model.materials[0].unlit);
    assert_eq!(glass.emissive, Vec3::new(1.0, 0.5, 0.25));
    let emissive = glass.emissive_texture.expect("emissive texture");
    assert_eq!((emissive.tex_coord, emissive.transform), (1, None));
    assert!(model.textures[emissive.texture].srgb);
    // The primitive keeps its default material.
    assert_eq!(model.meshes[0].primitives[0].material, Some(0));
    let count = |word: &str| model.warnings.iter().filter(|w| w.contains(word)).count();
    assert_eq!(count("KHR_materials_transmission"), 1, "{:?}", model.warnings);
    assert_eq!(count("KHR_materials_variants"), 1, "{:?}", model.warnings);
    let transmission = model.warnings.iter().find(|w| w.contains("KHR_materials_transmission")).unwrap();
    assert_mentions(transmission, &["material 1 'Glass'", "material 2 'Texture'"]);
}

#[test]
fn valid_json_forms_load() {
    let (mut json, bin) = textured();
    // Integers written as floats, extras of any type, a channel without a node, a scene without
    // nodes besides the one shown.
    json["meshes"][0]["primitives"][0]["indices"] = json!(0.0);
    json["accessors"][0]["count"] = json!(36.0);
    json["extras"] = json!(42);
    json["nodes"][1]["extras"] = json!("text");
    json["scenes"] = json!([{"nodes": [0]}, {"name": "empty"}]);
    json["animations"] = json!([{"channels": [{"sampler": 0, "target": {"path": "translation"}}],
        "samplers": [{"input": 3, "output": 3}]}]);
    let model = load_derived("Forms.glb", &json, &bin);
    assert_eq!(model.meshes[0].primitives[0].indices.len(), 36);
    assert!(model.animations[0].channels.is_empty());
    assert!(model.warnings.iter().any(|w| w.contains("target no node")), "{:?}", model.warnings);
}

#[test]
fn buffers_are_loaded_only_when_used() {
    let (mut json, bin) = textured();
    let buffers = json["buffers"].as_array_mut().unwrap();
    buffers.push(json!({"byteLength": 10, "uri": "missing.bin"}));
    buffers.push(json!({"byteLength": 10, "uri": "https://example.com/x.bin"}));
    buffers.push(json!({"byteLength": 10}));
    let model = load_derived("Unused.glb", &json, &bin);
    assert_eq!(model.meshes[0].primitives[0].triangle_count(), 12);

    // The same buffer, used: refused with its name.
    json["bufferViews"][1]["buffer"] = json!(1);
    let tmp = TempDir::new("used-missing");
    let msg = load_error(&tmp, "Used.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["buffer 1", "missing.bin"]);
}

#[test]
fn huge_counts_are_refused_before_allocating() {
    let (json, bin) = textured();
    let tmp = TempDir::new("huge");
    // A count of 2^31 in a small view.
    let mut huge = json.clone();
    huge["accessors"][2]["count"] = json!(1u64 << 31);
    let msg = load_error(&tmp, "Huge.glb", &make_glb(&huge, &bin));
    assert_mentions(&msg, &["accessor 2", "run past the end"]);
    // The same without a bufferView: zeros, bounded by the zero-fill budget.
    huge["accessors"][2].as_object_mut().unwrap().remove("bufferView");
    let msg = load_error(&tmp, "HugeZeros.glb", &make_glb(&huge, &bin));
    assert_mentions(&msg, &["accessor 2", "zero-filled", "limit"]);
    // A small one without a bufferView is zeros.
    let mut zeros = json.clone();
    zeros["accessors"][1].as_object_mut().unwrap().remove("bufferView");
    let model = load_derived("Zeros.glb", &zeros, &bin);
    // Zero normals cannot be normalised: they fall back to +Z.
    assert!(model.meshes[0].primitives[0].normals.iter().all(|n| *n == Vec3::Z));
}

#[test]
fn meshopt_compressed_box_decodes_to_a_unit_cube() {
    let model = load(&assets(), "gltf-transform/BoxMeshopt.glb");
    let prim = &model.meshes[0].primitives[0];
    assert_eq!(prim.triangle_count(), 12);
    let node = model.nodes.iter().find(|n| n.mesh == Some(0)).expect("mesh node").local.to_mat4();
    let world: Vec<Vec3> = prim.positions.iter().map(|p| node.transform_point3(*p)).collect();
    // Every vertex is a corner of the cube [-0.5, 0.5]^3 (quantised to 14 bits).
    assert!(world.iter().all(|p| (p.abs() - Vec3::splat(0.5)).abs().max_element() < 1e-3), "{world:?}");
    for t in prim.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| world[t[k] as usize]);
        let face = (b - a).cross(c - a).normalize();
        // Octahedral-free i8 normals: axis-aligned, and the winding agrees with them.
        let n = prim.normals[t[0] as usize];
        assert!(n.dot(face) > 0.99, "triangle {t:?}: face normal {face}, vertex normal {n}");
    }
}

#[test]
fn draco_is_refused_by_name_unless_a_fallback_is_stored() {
    let (mut json, bin) = textured();
    let draco = json!({"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}});
    json["meshes"][0]["primitives"][0]["extensions"] = draco;
    json["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
    let model = load_derived("DracoFallback.glb", &json, &bin);
    assert!(model.warnings.iter().any(|w| w.contains("KHR_draco_mesh_compression")), "{:?}", model.warnings);
    // Not listed as required, and no uncompressed data: refused, naming Draco once.
    json["accessors"][2].as_object_mut().unwrap().remove("bufferView");
    let tmp = TempDir::new("draco");
    let msg = load_error(&tmp, "Draco.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["KHR_draco_mesh_compression", "cannot decode"]);
    assert_eq!(msg.matches("KHR_draco_mesh_compression").count(), 1, "{msg}");
}

#[test]
fn emissive_strength_scales_the_emissive_factor() {
    // CornellBox's light: emissiveFactor [1, 1, 1] with KHR_materials_emissive_strength 100.
    let model = load_gltf(&assets().join("CornellBox.glb")).unwrap_or_else(|e| panic!("{e}"));
    let light = model.materials.iter().find(|m| m.name.as_deref() == Some("Emitter_Light_temp")).expect("the light");
    assert_eq!(light.emissive, Vec3::splat(100.0));
    assert!(model.materials.iter().filter(|m| !std::ptr::eq(*m, light)).all(|m| m.emissive == Vec3::ZERO));
    assert!(!model.warnings.iter().any(|w| w.contains("emissive_strength")), "{:?}", model.warnings);
}

#[test]
fn a_file_requiring_emissive_strength_is_read_with_it() {
    // Blender's exporter lists KHR_materials_emissive_strength as required when it writes it.
    let (mut json, bin) = glb_parts(&std::fs::read(assets().join("CornellBox.glb")).expect("CornellBox.glb"));
    json["extensionsRequired"] = json!(["KHR_materials_emissive_strength"]);
    let model = load_derived("EmissiveRequired.glb", &json, &bin);
    let light = model.materials.iter().find(|m| m.name.as_deref() == Some("Emitter_Light_temp")).expect("the light");
    assert_eq!(light.emissive, Vec3::splat(100.0));
    assert!(!model.warnings.iter().any(|w| w.contains("emissive_strength")), "{:?}", model.warnings);
}
