//! Loader, animation and skinning tests against real files from other tools
//! (`tests/assets`, see its `SOURCES.md`); files broken on purpose, and files made to hold what
//! none of them has, are in `damaged`.

mod damaged;

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use serde_json::{json, Value};

use super::{load_gltf, load_gltf_slice};
use crate::error::Error;
use crate::scene::animation::{pose_at, rest_pose, TimeMode};
use crate::scene::model::{Filter, Model, Property, Transform, Wrap, MAX_JOINTS};
use crate::scene::skinning::{joint_matrices, skin_positions_normals, world_matrices};

const ALL: [&str; 7] = [
    "Box.glb",
    "BoxAnimated.glb",
    "BoxTextured.glb",
    "CornellBox.glb",
    "RiggedSimple.glb",
    "SimpleSkin.gltf",
    "TorusKnot.glb",
];

/// The repository's real glTF files (`tests/assets`, see its `SOURCES.md`); the tests need them
/// (a skipped test proves nothing), so their absence is a failure that says where it looked.
pub(super) fn assets() -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/assets");
    assert!(dir.is_dir(), "{} not found: the glTF tests need the test asset folder", dir.display());
    dir
}

pub(super) fn load(dir: &Path, name: &str) -> Model {
    let path = dir.join(name);
    match load_gltf(&path) {
        Ok(model) => model,
        Err(e) => panic!("{name} failed to load: {e}"),
    }
}

/// A directory under the system temp dir, removed on drop.
pub(super) struct TempDir(PathBuf);

impl TempDir {
    pub(super) fn new(tag: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("nostencil-gltf-{}-{tag}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }

    pub(super) fn write(&self, name: &str, bytes: &[u8]) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// JSON and BIN chunks of a well-formed GLB.
pub(crate) fn glb_parts(bytes: &[u8]) -> (Value, Vec<u8>) {
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let json_len = u32_at(12);
    let json: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin_at = 20 + json_len;
    let bin = if bin_at + 8 <= bytes.len() {
        let bin_len = u32_at(bin_at);
        bytes[bin_at + 8..bin_at + 8 + bin_len].to_vec()
    } else {
        Vec::new()
    };
    (json, bin)
}

pub(crate) fn make_glb(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut text = serde_json::to_vec(json).unwrap();
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    let mut bin = bin.to_vec();
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + text.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
    }
    out
}

/// Byte offset in the BIN chunk of element `element` of accessor `accessor` (no sparse).
fn element_offset(json: &Value, accessor: usize, element: usize, elem_size: usize) -> usize {
    let acc = &json["accessors"][accessor];
    let view = &json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
    let stride = view["byteStride"].as_u64().map_or(elem_size, |s| s as usize);
    view["byteOffset"].as_u64().unwrap_or(0) as usize
        + acc["byteOffset"].as_u64().unwrap_or(0) as usize
        + element * stride
}

/// Loads `bytes` written to `name` in a temp dir and returns the error message, checking it is
/// an `Error::Asset` that names the file.
pub(super) fn load_error(tmp: &TempDir, name: &str, bytes: &[u8]) -> String {
    let path = tmp.write(name, bytes);
    match load_gltf(&path) {
        Ok(_) => panic!("{name}: loaded, but it is broken"),
        Err(e @ Error::Asset { .. }) => {
            let msg = e.to_string();
            assert!(msg.contains(name), "error does not name the file: {msg}");
            msg
        }
        Err(e) => panic!("{name}: expected Error::Asset, got {e:?}"),
    }
}

pub(super) fn assert_mentions(msg: &str, words: &[&str]) {
    for w in words {
        assert!(msg.contains(w), "expected '{w}' in: {msg}");
    }
}

#[test]
fn every_asset_loads_poses_and_skins_to_finite_values() {
    let dir = assets();
    for name in ALL {
        let model = load(&dir, name);
        for w in &model.warnings {
            eprintln!("{name}: warning: {w}");
        }
        assert!(!model.meshes.is_empty(), "{name}: no meshes");
        assert!(!model.roots.is_empty(), "{name}: no root nodes");
        for mesh in &model.meshes {
            for prim in &mesh.primitives {
                let n = prim.positions.len();
                assert_eq!(prim.normals.len(), n, "{name}");
                assert!(prim.indices.len() % 3 == 0 && !prim.indices.is_empty());
                assert!(prim.indices.iter().all(|&i| (i as usize) < n));
                assert!(prim.normals.iter().all(|v| (v.length() - 1.0).abs() < 1e-4));
                if let Some(w) = &prim.weights {
                    assert!(w.iter().all(|w| (w.iter().sum::<f32>() - 1.0).abs() < 1e-5));
                }
            }
        }
        let mut poses = vec![rest_pose(&model)];
        for a in 0..model.animations.len() {
            for t in [0.0, 0.3, 1.0, 1e6, -2.0] {
                poses.push(pose_at(&model, a, t, TimeMode::Loop).unwrap());
                poses.push(pose_at(&model, a, t, TimeMode::Clamp).unwrap());
            }
        }
        for pose in &poses {
            let world = world_matrices(&model, pose);
            assert!(world.iter().all(|m| m.is_finite()), "{name}");
            for (i, node) in model.nodes.iter().enumerate() {
                let (Some(s), Some(m)) = (node.skin, node.mesh) else {
                    continue;
                };
                let palette = joint_matrices(&model, s, &world, world[i]).unwrap();
                for prim in &model.meshes[m].primitives {
                    let (mut p, mut n) = (Vec::new(), Vec::new());
                    skin_positions_normals(prim, &palette, &mut p, &mut n).unwrap();
                    assert!(p.iter().chain(&n).all(|v| v.is_finite()), "{name}");
                }
            }
        }
    }
}

#[test]
fn box_has_24_vertices_36_indices_one_mesh() {
    let dir = assets();
    let model = load(&dir, "Box.glb");
    assert_eq!(model.meshes.len(), 1);
    let prim = &model.meshes[0].primitives[..];
    assert_eq!(prim.len(), 1);
    assert_eq!(prim[0].positions.len(), 24);
    assert_eq!(prim[0].indices.len(), 36);
    assert_eq!(prim[0].source_index_width, Some(2));
    assert!(!prim[0].normals_generated);
    assert!(prim[0].uv0.is_none() && prim[0].joints.is_none());
    assert_eq!(prim[0].material, Some(0));
    // Node 0 turns Y-up into the file's Z-up with a matrix; node 1 holds the mesh.
    assert_eq!(model.roots, [0]);
    assert_eq!(model.nodes[1].parent, Some(0));
    assert_eq!(model.nodes[1].mesh, Some(0));
    let world = world_matrices(&model, &rest_pose(&model));
    let expected =
        Mat4::from_cols_array(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    assert!(world[1].abs_diff_eq(expected, 1e-6), "{}", world[1]);
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
}

#[test]
fn torus_knot_has_3200_vertices_6400_u16_triangles_and_is_closed() {
    let dir = assets();
    let model = load(&dir, "TorusKnot.glb");
    let prim = &model.meshes[0].primitives[0];
    assert_eq!(prim.positions.len(), 3200);
    assert_eq!(prim.triangle_count(), 6400);
    assert_eq!(prim.source_index_width, Some(2));
    // Closed: every undirected edge is shared by exactly two triangles, in opposite directions.
    let mut edges = std::collections::HashMap::new();
    for t in prim.indices.chunks_exact(3) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *edges.entry((a, b)).or_insert(0) += 1;
        }
    }
    assert!(edges.iter().all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1)));
    // V - E + F = 0 for a torus.
    assert_eq!(3200 - (edges.len() / 2) as i64 + 6400, 0);
}

#[test]
fn cornell_box_has_four_meshes_with_lightmap_uvs() {
    let dir = assets();
    let model = load(&dir, "CornellBox.glb");
    assert_eq!(model.meshes.len(), 4);
    let prims: Vec<_> = model.meshes.iter().flat_map(|m| &m.primitives).collect();
    assert_eq!(prims.len(), 6);
    for prim in &prims {
        let uv1 = prim.uv1.as_ref().expect("TEXCOORD_1");
        assert_eq!(uv1.len(), prim.positions.len());
        assert!(uv1.iter().all(|uv| uv.min_element() >= 0.0 && uv.max_element() <= 1.0));
    }
    // The light's COLOR_0 is normalised UNSIGNED_SHORT.
    let colors = model.meshes[0].primitives[0].colors.as_ref().expect("COLOR_0");
    assert!(colors.iter().all(|c| c.min_element() >= 0.0 && c.max_element() <= 1.0));
    assert_eq!(model.materials.len(), 5);
    assert_eq!(model.nodes[1].name.as_deref(), Some("large.box"));
    // KHR_materials_emissive_strength is read (see extension_tests), so nothing is warned.
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
}

#[test]
fn box_textured_decodes_its_png() {
    let dir = assets();
    let model = load(&dir, "BoxTextured.glb");
    assert_eq!(model.textures.len(), 1);
    let tex = &model.textures[0];
    assert_eq!((tex.width, tex.height), (211, 211));
    assert_eq!(tex.pixels.len(), 211 * 211 * 4);
    assert!(tex.srgb);
    assert_eq!((tex.sampler.wrap_s, tex.sampler.wrap_t), (Wrap::Repeat, Wrap::Repeat));
    assert!(tex.pixels.chunks_exact(4).any(|p| p[0] != p[1] || p[1] != p[2]));
    let material = &model.materials[0];
    let texture_ref = material.base_color_texture.expect("base colour texture");
    assert_eq!((texture_ref.texture, texture_ref.tex_coord), (0, 0));
    let uv0 = model.meshes[0].primitives[0].uv0.as_ref().expect("TEXCOORD_0");
    assert!(uv0.iter().any(|uv| uv.max_element() > 1.0 || uv.min_element() < 0.0));
}

#[test]
fn rigged_simple_has_two_joints_and_trs_animation() {
    let dir = assets();
    let model = load(&dir, "RiggedSimple.glb");
    assert_eq!(model.skins.len(), 1);
    assert_eq!(model.skins[0].joints, [3, 4]);
    assert_eq!(model.skins[0].skeleton, Some(3));
    assert_eq!(model.skins[0].inverse_bind.len(), 2);
    assert_eq!(model.nodes[2].skin, Some(0));
    let anim = &model.animations[0];
    let mut props: Vec<_> = anim.channels.iter().map(|c| (c.node, c.property)).collect();
    props.sort_by_key(|(n, p)| (*n, *p as u8));
    assert_eq!(props, [(4, Property::Translation), (4, Property::Rotation), (4, Property::Scale)]);
    assert!((anim.duration - 2.083333).abs() < 1e-4, "{}", anim.duration);
    let prim = &model.meshes[0].primitives[0];
    assert_eq!(prim.positions.len(), 160);
    assert!(prim.is_skinned());
}

#[test]
fn simple_skin_embedded_buffers_and_computed_normals() {
    let dir = assets();
    let model = load(&dir, "SimpleSkin.gltf");
    let prim = &model.meshes[0].primitives[0];
    assert_eq!(prim.positions.len(), 10);
    assert_eq!(prim.triangle_count(), 8);
    assert!(prim.normals_generated);
    // A flat strip in the z = 0 plane, wound counter-clockwise seen from +z.
    assert!(prim.normals.iter().all(|n| (*n - Vec3::Z).length() < 1e-6), "{:?}", prim.normals);
    assert_eq!(model.skins[0].joints, [1, 2]);
    assert_eq!(model.animations[0].channels.len(), 1);
    assert_eq!(model.animations[0].channels[0].property, Property::Rotation);
}

#[test]
fn box_animated_moves_its_nodes_and_has_two_meshes() {
    let dir = assets();
    let model = load(&dir, "BoxAnimated.glb");
    assert_eq!(model.meshes.len(), 2);
    assert_eq!(model.animations.len(), 1);
    let anim = &model.animations[0];
    assert_eq!(anim.channels.len(), 2);
    assert!(anim.channels.iter().any(|c| c.node == 2 && c.property == Property::Rotation));
    assert!(anim.channels.iter().any(|c| c.node == 0 && c.property == Property::Translation));
    let at = |t: f32| world_matrices(&model, &pose_at(&model, 0, t, TimeMode::Clamp).unwrap());
    let (a, b) = (at(0.0), at(anim.duration * 0.6));
    // Node 2 (inner box) both moves with node 0 and turns.
    assert!(!a[2].abs_diff_eq(b[2], 1e-3));
    // Node 3 has no animation and no animated ancestor.
    assert!(a[3].abs_diff_eq(b[3], 0.0));
}

/// Skins every skinned node of `model` with `pose` and returns (rest positions, posed) pairs.
fn skinned(model: &Model, pose: &[Transform]) -> Vec<(Vec<Vec3>, Vec<Vec3>)> {
    let world = world_matrices(model, pose);
    let mut out = Vec::new();
    for (i, node) in model.nodes.iter().enumerate() {
        let (Some(s), Some(m)) = (node.skin, node.mesh) else {
            continue;
        };
        let palette = joint_matrices(model, s, &world, world[i]).unwrap();
        for prim in &model.meshes[m].primitives {
            let (mut p, mut n) = (Vec::new(), Vec::new());
            skin_positions_normals(prim, &palette, &mut p, &mut n).unwrap();
            out.push((prim.positions.clone(), p));
        }
    }
    out
}

/// In the rest pose the skin is in its bind pose: every joint matrix is the same rigid
/// transform, and the skinned mesh is the bind mesh moved by it. For SimpleSkin that transform is
/// the identity, so skinned positions equal the file's positions. RiggedSimple's inverse bind
/// matrices were made against its Z_UP node, not against the Cylinder mesh node (which sits under
/// Armature, turned -90 degrees about the cylinder's own axis); glTF ignores a skinned mesh
/// node's transform, so the palette is that 90-degree turn and, in world space, the mesh lands
/// exactly where Z_UP puts the bind positions.
#[test]
fn rest_pose_skinning_reproduces_the_bind_mesh() {
    let dir = assets();
    for name in ["RiggedSimple.glb", "SimpleSkin.gltf"] {
        let model = load(&dir, name);
        let world = world_matrices(&model, &rest_pose(&model));
        let (mesh_node, node) = model.nodes.iter().enumerate().find(|(_, n)| n.skin.is_some()).unwrap();
        let palette = joint_matrices(&model, 0, &world, world[mesh_node]).unwrap();
        let common = palette[0];
        for m in &palette {
            assert!(m.abs_diff_eq(common, 1e-5), "{name}: joints disagree in the rest pose");
        }
        let prim = &model.meshes[node.mesh.unwrap()].primitives[0];
        let (mut posed, mut normals) = (Vec::new(), Vec::new());
        skin_positions_normals(prim, &palette, &mut posed, &mut normals).unwrap();
        for (bind, p) in prim.positions.iter().zip(&posed) {
            let expected = common.transform_point3(*bind);
            assert!((expected - *p).length() < 1e-5, "{name}: {p} vs {expected}");
        }
        if name == "SimpleSkin.gltf" {
            assert!(common.abs_diff_eq(Mat4::IDENTITY, 1e-6), "{common}");
            for (bind, p) in prim.positions.iter().zip(&posed) {
                assert!((*bind - *p).length() < 1e-5, "{bind} vs {p}");
            }
        } else {
            let quarter = Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2);
            assert!(common.abs_diff_eq(quarter, 1e-5), "{common}");
            assert!((world[mesh_node] * common).abs_diff_eq(world[0], 1e-5));
        }
    }
}

#[test]
fn rigged_simple_animation_moves_the_upper_vertices_only() {
    let dir = assets();
    let model = load(&dir, "RiggedSimple.glb");
    let prim = &model.meshes[0].primitives[0];
    let weights = prim.weights.as_ref().unwrap();
    let joints = prim.joints.as_ref().unwrap();
    // Weight of joint 1 (Bone.001, the animated one) per vertex.
    let upper: Vec<f32> =
        joints.iter().zip(weights).map(|(j, w)| (0..4).filter(|&k| j[k] == 1).map(|k| w[k]).sum()).collect();
    assert!(upper.contains(&0.0) && upper.iter().any(|&w| w > 0.9));
    let duration = model.animations[0].duration;
    let (_, rest) = skinned(&model, &rest_pose(&model)).remove(0);
    let pose = pose_at(&model, 0, duration * 0.5, TimeMode::Clamp).unwrap();
    let (_, posed) = skinned(&model, &pose).remove(0);
    let moved: Vec<f32> = rest.iter().zip(&posed).map(|(a, b)| (*a - *b).length()).collect();
    for (v, (&w, &d)) in upper.iter().zip(&moved).enumerate() {
        if w == 0.0 {
            assert!(d < 1e-5, "root vertex {v} moved by {d}");
        }
    }
    let least = upper.iter().zip(&moved).filter(|(&w, _)| w > 0.9).map(|(_, &d)| d).fold(f32::INFINITY, f32::min);
    assert!(least > 0.1, "upper vertices barely move ({least})");
}

#[test]
fn re_posing_a_gltf_scene_equals_loading_it_at_that_time() {
    let dir = assets();
    for name in ["RiggedSimple.glb", "BoxAnimated.glb", "SimpleSkin.gltf"] {
        let path = dir.join(name);
        let mut scene = crate::scene::scene_from_gltf(&path, 0.0).unwrap();
        assert!(scene.is_animated(), "{name}");
        for time in [0.4, 1.3] {
            scene.pose_at(time).unwrap();
            let built = crate::scene::scene_from_gltf(&path, time).unwrap();
            let mut moved = 0;
            // The ground is fitted to the pose a scene is built in; the model's objects move.
            for (a, b) in scene.objects.iter().zip(&built.objects).filter(|(a, _)| a.rig.is_some()) {
                assert_eq!(a.transform, b.transform, "{name} at {time}: {}", a.name);
                let palette = |o: &crate::scene::SceneObject| o.skin.as_ref().map(|s| s.joint_matrices.clone());
                assert_eq!(palette(a), palette(b), "{name} at {time}: {}", a.name);
                moved += (a.rig.is_some()) as usize;
            }
            assert!(moved > 0, "{name}");
        }
    }
    assert!(!crate::scene::scene_from_gltf(&dir.join("Box.glb"), 0.0).unwrap().is_animated());
}

#[test]
fn a_textured_material_reaches_the_scene_with_its_texture() {
    // BoxTextured's material: white factor, base colour texture 0 on TEXCOORD_0.
    let scene = crate::scene::scene_from_gltf(&assets().join("BoxTextured.glb"), 0.0).unwrap();
    let material = scene.material_of(&scene.objects[0]);
    let texture = material.base_color_texture.expect("a base colour texture");
    let model = load(&assets(), "BoxTextured.glb");
    assert_eq!(*scene.textures[texture.texture], model.textures[0]);
    assert_eq!(texture.tex_coord, 0);
    assert!(
        scene.meshes[scene.objects[0].mesh].data.uvs.len() == scene.meshes[scene.objects[0].mesh].data.positions.len()
    );
}

#[test]
fn position_accessors_without_bounds_load_with_a_warning() {
    // The spec requires POSITION min/max; exporters omit them; nothing here reads them.
    let dir = assets();
    let original = load(&dir, "Box.glb");
    let (mut json, bin) = glb_parts(&std::fs::read(dir.join("Box.glb")).unwrap());
    let accessor = json["accessors"][2].as_object_mut().unwrap();
    accessor.remove("min");
    accessor.remove("max");
    let model = load_gltf_slice(&make_glb(&json, &bin), Path::new("NoBounds.glb")).unwrap();
    assert_eq!(model.meshes[0].primitives[0].positions, original.meshes[0].primitives[0].positions);
    assert!(
        model.warnings.iter().any(|w| w.contains("POSITION accessor(s) 2 lack the min/max")),
        "{:?}",
        model.warnings
    );
}

#[test]
fn invalid_optional_enum_values_fall_back_to_their_defaults() {
    let dir = assets();
    let (mut json, bin) = glb_parts(&std::fs::read(dir.join("BoxTextured.glb")).unwrap());
    json["samplers"][0]["magFilter"] = json!(0);
    json["bufferViews"][0]["target"] = json!(1);
    json["materials"][0]["alphaMode"] = json!("Blend");
    let model = load_gltf_slice(&make_glb(&json, &bin), Path::new("Sloppy.glb")).unwrap();
    for expected in ["samplers[0].magFilter 0", "bufferViews[0].target 1", "materials[0].alphaMode \"Blend\""] {
        assert!(model.warnings.iter().any(|w| w.contains(expected)), "{expected}: {:?}", model.warnings);
    }
    assert_eq!(model.textures[0].sampler.mag_filter, Filter::Linear);
    // Required enums still fail, by name, when read (an unused accessor of an unknown type is
    // valid glTF).
    let (mut json, bin) = glb_parts(&std::fs::read(dir.join("Box.glb")).unwrap());
    json["accessors"][2]["type"] = json!("VEC7");
    let msg = load_gltf_slice(&make_glb(&json, &bin), Path::new("Vec7.glb")).unwrap_err().to_string();
    assert_mentions(&msg, &["Vec7.glb", "accessor 2", "`type` is none of"]);
    json["accessors"][2]["componentType"] = json!(5127);
    let msg = load_gltf_slice(&make_glb(&json, &bin), Path::new("Vec7.glb")).unwrap_err().to_string();
    assert_mentions(&msg, &["Vec7.glb", "accessors[2].componentType"]);
}

#[test]
fn only_the_files_scene_is_drawn() {
    // Box.glb with a second scene holding another instance of the box: `scene: 1` shows that
    // one only; orphan nodes are not drawn either.
    let dir = assets();
    let (mut json, bin) = glb_parts(&std::fs::read(dir.join("Box.glb")).unwrap());
    let nodes = json["nodes"].as_array_mut().unwrap();
    nodes.push(json!({ "mesh": 0, "translation": [5.0, 0.0, 0.0] }));
    nodes.push(json!({ "mesh": 0, "translation": [-5.0, 0.0, 0.0] })); // in no scene
    json["scenes"] = json!([{ "nodes": [0] }, { "nodes": [2] }]);
    json["scene"] = json!(1);
    let tmp = TempDir::new("scenes");
    let path = tmp.write("TwoScenes.glb", &make_glb(&json, &bin));
    let scene = crate::scene::scene_from_gltf(&path, 0.0).unwrap();
    let boxes: Vec<_> = scene.objects.iter().filter(|o| o.name != "ground").collect();
    assert_eq!(boxes.len(), 1, "{:?}", boxes.iter().map(|o| &o.name).collect::<Vec<_>>());
    assert_eq!(boxes[0].transform.w_axis.truncate(), Vec3::new(5.0, 0.0, 0.0));
}
