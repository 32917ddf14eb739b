//! Loader, animation and skinning tests against real files from other tools
//! (`tests/assets`, see its `SOURCES.md`), and against broken files derived from them.

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
pub(super) fn glb_parts(bytes: &[u8]) -> (Value, Vec<u8>) {
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

pub(super) fn make_glb(json: &Value, bin: &[u8]) -> Vec<u8> {
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
fn truncated_glb_files_are_rejected_at_every_length() {
    let dir = assets();
    let bytes = std::fs::read(dir.join("Box.glb")).unwrap();
    let path = Path::new("cut/Box.glb");
    for len in 0..bytes.len() {
        match load_gltf_slice(&bytes[..len], path) {
            Ok(_) => panic!("Box.glb cut to {len} bytes loaded"),
            Err(e) => assert!(e.to_string().contains("cut/Box.glb"), "{e}"),
        }
    }
    let tmp = TempDir::new("truncated");
    for name in ["RiggedSimple.glb", "TorusKnot.glb", "BoxTextured.glb"] {
        let bytes = std::fs::read(dir.join(name)).unwrap();
        let msg = load_error(&tmp, name, &bytes[..bytes.len() / 2]);
        assert_mentions(&msg, &["truncated GLB", "header says"]);
    }
}

#[test]
fn buffer_view_past_its_buffer_is_rejected() {
    let dir = assets();
    let (mut json, bin) = glb_parts(&std::fs::read(dir.join("Box.glb")).unwrap());
    json["bufferViews"][1]["byteLength"] = json!(100_000);
    let tmp = TempDir::new("view");
    let msg = load_error(&tmp, "BadView.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["bufferView 1", "points past the end of buffer 0"]);

    // An accessor that runs off the end of its (valid) view.
    let (mut json, bin) = glb_parts(&std::fs::read(dir.join("Box.glb")).unwrap());
    json["accessors"][2]["byteOffset"] = json!(400);
    let msg = load_error(&tmp, "BadOffset.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["POSITION", "accessor 2", "run past the end"]);
}

#[test]
fn accessors_of_the_wrong_type_are_rejected() {
    let dir = assets();
    let tmp = TempDir::new("type");
    let box_glb = std::fs::read(dir.join("Box.glb")).unwrap();
    let (mut json, bin) = glb_parts(&box_glb);
    json["accessors"][2]["type"] = json!("VEC2");
    let msg = load_error(&tmp, "Vec2Positions.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["POSITION", "accessor 2 has type VEC2, expected VEC3"]);

    let (mut json, bin) = glb_parts(&box_glb);
    json["accessors"][2]["componentType"] = json!(5123);
    let msg = load_error(&tmp, "ShortPositions.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["componentType UNSIGNED_SHORT, expected FLOAT"]);

    let (mut json, bin) = glb_parts(&box_glb);
    json["accessors"][0]["componentType"] = json!(5126);
    let msg = load_error(&tmp, "FloatIndices.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["indices", "FLOAT"]);

    let (mut json, bin) = glb_parts(&box_glb);
    json["accessors"][1]["count"] = json!(23);
    let msg = load_error(&tmp, "ShortNormals.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["NORMAL has 23 elements but POSITION has 24"]);
}

#[test]
fn indices_out_of_range_are_rejected() {
    let dir = assets();
    let (mut json, bin) = glb_parts(&std::fs::read(dir.join("Box.glb")).unwrap());
    json["accessors"][1]["count"] = json!(20);
    json["accessors"][2]["count"] = json!(20);
    let tmp = TempDir::new("index");
    let msg = load_error(&tmp, "FewVertices.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["indices", "out of range of the 20 vertices"]);
}

#[test]
fn nan_positions_are_rejected() {
    let dir = assets();
    let (json, mut bin) = glb_parts(&std::fs::read(dir.join("Box.glb")).unwrap());
    let at = element_offset(&json, 2, 5, 12) + 4;
    bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let tmp = TempDir::new("nan");
    let msg = load_error(&tmp, "NaN.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["POSITION of vertex 5 is not finite"]);
}

#[test]
fn skins_over_max_joints_are_rejected() {
    // RiggedSimple's skin grown to `joints` joints (the extra ones unused by any vertex).
    let dir = assets();
    let with_joints = |joints: usize| {
        let (mut json, bin) = glb_parts(&std::fs::read(dir.join("RiggedSimple.glb")).unwrap());
        let nodes = json["nodes"].as_array_mut().unwrap();
        let first_new = nodes.len();
        let extra = joints - 2;
        for k in 0..extra {
            nodes.push(json!({ "name": format!("extra{k}") }));
        }
        let mut children: Vec<Value> = json["nodes"][4]["children"].as_array().cloned().unwrap_or_default();
        children.extend((first_new..first_new + extra).map(|n| json!(n)));
        json["nodes"][4]["children"] = Value::Array(children);
        let list = json["skins"][0]["joints"].as_array_mut().unwrap();
        list.extend((first_new..first_new + extra).map(|n| json!(n)));
        assert_eq!(list.len(), joints);
        // Optional: without it every inverse bind matrix is the identity.
        json["skins"][0].as_object_mut().unwrap().remove("inverseBindMatrices");
        make_glb(&json, &bin)
    };
    let tmp = TempDir::new("joints");
    // A 65-bone rig, common in exported characters, fits the 16 KiB palette.
    let path = tmp.write("65Joints.glb", &with_joints(65));
    assert_eq!(load_gltf(&path).unwrap().skins[0].joints.len(), 65);
    let too_many = MAX_JOINTS + 1;
    let msg = load_error(&tmp, "TooMany.glb", &with_joints(too_many));
    assert_mentions(&msg, &["skin 0", &format!("{too_many} joints"), &format!("at most {MAX_JOINTS}")]);
}

#[test]
fn joint_indices_outside_the_skin_are_rejected() {
    let dir = assets();
    let (json, mut bin) = glb_parts(&std::fs::read(dir.join("RiggedSimple.glb")).unwrap());
    // JOINTS_0 is accessor 1 (VEC4 UNSIGNED_SHORT): point every slot of vertex 7 at joint 5.
    let at = element_offset(&json, 1, 7, 8);
    for k in 0..4 {
        bin[at + 2 * k..at + 2 * k + 2].copy_from_slice(&5u16.to_le_bytes());
    }
    let tmp = TempDir::new("jointindex");
    let msg = load_error(&tmp, "BadJoint.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["JOINTS_0", "vertex 7", "joint 5", "has 2 joints"]);
}

#[test]
fn key_times_that_do_not_increase_are_rejected() {
    let dir = assets();
    let (json, mut bin) = glb_parts(&std::fs::read(dir.join("RiggedSimple.glb")).unwrap());
    // The input accessor of the first sampler: repeat key 2's time at key 3.
    let input = json["animations"][0]["samplers"][0]["input"].as_u64().unwrap() as usize;
    let t2 = element_offset(&json, input, 2, 4);
    let t3 = element_offset(&json, input, 3, 4);
    let copy = bin[t2..t2 + 4].to_vec();
    bin[t3..t3 + 4].copy_from_slice(&copy);
    let tmp = TempDir::new("times");
    let msg = load_error(&tmp, "RepeatedTime.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["animation 0", "not strictly increasing", "key 3"]);
}

#[test]
fn node_cycles_are_rejected() {
    let dir = assets();
    let (mut json, bin) = glb_parts(&std::fs::read(dir.join("Box.glb")).unwrap());
    json["nodes"][1]["children"] = json!([0]);
    let tmp = TempDir::new("cycle");
    let msg = load_error(&tmp, "Cycle.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["cycle"]);
}

#[test]
fn missing_and_non_gltf_files_are_rejected() {
    let tmp = TempDir::new("notgltf");
    let missing = tmp.0.join("DoesNotExist.glb");
    let msg = load_gltf(&missing).unwrap_err().to_string();
    assert_mentions(&msg, &["DoesNotExist.glb", "cannot read the file"]);

    let msg = load_error(&tmp, "notes.gltf", b"these are not the droids\n");
    assert_mentions(&msg, &["not a glTF file"]);
    let msg = load_error(&tmp, "picture.glb", b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR");
    assert_mentions(&msg, &["not a glTF file"]);
    let msg = load_error(&tmp, "other.gltf", br#"{"hello": "world"}"#);
    assert_mentions(&msg, &["not a glTF 2.0 document", "asset"]);
    let msg = load_error(&tmp, "old.gltf", br#"{"asset": {"version": "1.0"}}"#);
    assert_mentions(&msg, &["version 1.0"]);
}

#[test]
fn external_buffers_load_and_missing_ones_are_named() {
    let dir = assets();
    let text = std::fs::read(dir.join("SimpleSkin.gltf")).unwrap();
    let mut json: Value = serde_json::from_slice(&text).unwrap();
    let uri = json["buffers"][1]["uri"].as_str().unwrap().to_string();
    let data = super::buffers::decode_data_uri(&uri).unwrap().unwrap();
    let tmp = TempDir::new("external");
    tmp.write("skin weights.bin", &data);
    json["buffers"][1]["uri"] = json!("skin%20weights.bin");
    let path = tmp.write("External.gltf", &serde_json::to_vec(&json).unwrap());
    let external = load_gltf(&path).unwrap();
    let embedded = load(&dir, "SimpleSkin.gltf");
    let (a, b) = (&external.meshes[0].primitives[0], &embedded.meshes[0].primitives[0]);
    assert_eq!(a.joints, b.joints);
    assert_eq!(a.weights, b.weights);

    std::fs::remove_file(tmp.0.join("skin weights.bin")).unwrap();
    let msg = load_gltf(&path).unwrap_err().to_string();
    assert_mentions(&msg, &["External.gltf", "buffer 1", "skin%20weights.bin", "cannot read"]);

    json["buffers"][1]["uri"] = json!("data:application/octet-stream;base64,@@@@");
    let msg = load_error(&tmp, "BadBase64.gltf", &serde_json::to_vec(&json).unwrap());
    assert_mentions(&msg, &["buffer 1", "base64"]);

    json["buffers"][1]["uri"] = json!("data:application/octet-stream;base64,AAAA");
    let msg = load_error(&tmp, "ShortBuffer.gltf", &serde_json::to_vec(&json).unwrap());
    assert_mentions(&msg, &["buffer 1", "byteLength is 320 but only 3 bytes"]);
}

#[test]
fn external_images_load_and_missing_ones_are_named() {
    let dir = assets();
    let (mut json, bin) = glb_parts(&std::fs::read(dir.join("BoxTextured.glb")).unwrap());
    let view = json["images"][0]["bufferView"].as_u64().unwrap() as usize;
    let start = json["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
    let len = json["bufferViews"][view]["byteLength"].as_u64().unwrap() as usize;
    let tmp = TempDir::new("image");
    tmp.write("texture.png", &bin[start..start + len]);
    tmp.write("box.bin", &bin);
    json["images"][0] = json!({ "uri": "texture.png" });
    json["buffers"][0]["uri"] = json!("box.bin");
    let path = tmp.write("Textured.gltf", &serde_json::to_vec(&json).unwrap());
    let model = load_gltf(&path).unwrap();
    assert_eq!((model.textures[0].width, model.textures[0].height), (211, 211));

    std::fs::remove_file(tmp.0.join("texture.png")).unwrap();
    let msg = load_gltf(&path).unwrap_err().to_string();
    assert_mentions(&msg, &["Textured.gltf", "image 0", "texture.png", "cannot read"]);

    // A corrupt PNG is an error naming the format.
    let mut png = bin[start..start + len].to_vec();
    png[40..60].fill(0xAB);
    tmp.write("texture.png", &png);
    let msg = load_gltf(&path).unwrap_err().to_string();
    assert_mentions(&msg, &["PNG does not decode"]);

    // JPEG is the other core format (whatever the file name says): decoded, colours kept
    // within JPEG's loss; a broken one is an error naming JPEG.
    let original = image::load_from_memory(&bin[start..start + len]).unwrap().to_rgb8();
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 95).encode_image(&original).unwrap();
    tmp.write("texture.png", &jpeg);
    let model = load_gltf(&path).unwrap();
    let texture = &model.textures[0];
    assert_eq!((texture.width, texture.height), (211, 211));
    assert!(model.materials[0].base_color_texture.is_some());
    let worst = original
        .as_raw()
        .chunks_exact(3)
        .zip(texture.pixels.chunks_exact(4))
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] as i32 - b[c] as i32).abs()))
        .max()
        .unwrap();
    assert!(worst < 64, "JPEG texels differ from the PNG by up to {worst}");
    let mean: f64 = original
        .as_raw()
        .chunks_exact(3)
        .zip(texture.pixels.chunks_exact(4))
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] as f64 - b[c] as f64).abs()))
        .sum::<f64>()
        / (211.0 * 211.0 * 3.0);
    assert!(mean < 3.0, "JPEG texels differ from the PNG by {mean} on average");
    tmp.write("texture.png", b"\xff\xd8\xff\xe0 truncated jpeg");
    let msg = load_gltf(&path).unwrap_err().to_string();
    assert_mentions(&msg, &["Textured.gltf", "image 0", "JPEG does not decode"]);

    // Formats glTF core does not have (WebP, KTX2 through extensions) are a warning: the
    // material keeps its base colour factor.
    tmp.write("texture.png", b"RIFF\x10\0\0\0WEBPVP8 ");
    let model = load_gltf(&path).unwrap();
    assert!(model.textures.is_empty());
    assert!(model.materials[0].base_color_texture.is_none());
    assert!(model.warnings.iter().any(|w| w.contains("WebP")), "{:?}", model.warnings);
}

#[test]
fn points_and_lines_are_skipped_with_a_warning() {
    let dir = assets();
    let (mut json, bin) = glb_parts(&std::fs::read(dir.join("BoxAnimated.glb")).unwrap());
    json["meshes"][0]["primitives"][0]["mode"] = json!(1);
    let model = load_gltf_slice(&make_glb(&json, &bin), Path::new("Lines.glb")).unwrap();
    assert!(model.meshes[0].primitives.is_empty());
    assert_eq!(model.meshes[1].primitives.len(), 1);
    assert!(model.warnings.iter().any(|w| w.contains("Lines")), "{:?}", model.warnings);
}

#[test]
fn unnormalised_and_zero_weights_are_repaired() {
    let dir = assets();
    let (json, mut bin) = glb_parts(&std::fs::read(dir.join("RiggedSimple.glb")).unwrap());
    // WEIGHTS_0 is accessor 4 (VEC4 FLOAT): vertex 0 sums to 0.5, vertex 1 to 0.
    let w0 = element_offset(&json, 4, 0, 16);
    let w1 = element_offset(&json, 4, 1, 16);
    for (k, w) in [0.25f32, 0.25, 0.0, 0.0].iter().enumerate() {
        bin[w0 + 4 * k..w0 + 4 * k + 4].copy_from_slice(&w.to_le_bytes());
        bin[w1 + 4 * k..w1 + 4 * k + 4].copy_from_slice(&0f32.to_le_bytes());
    }
    let model = load_gltf_slice(&make_glb(&json, &bin), Path::new("Weights.glb")).unwrap();
    let weights = model.meshes[0].primitives[0].weights.as_ref().unwrap();
    assert_eq!(weights[0], [0.5, 0.5, 0.0, 0.0]);
    assert_eq!(weights[1], [1.0, 0.0, 0.0, 0.0]);
    assert!(model.warnings.iter().any(|w| w.contains("all-zero")));
    assert!(model.warnings.iter().any(|w| w.contains("renormalised")));
}

#[test]
fn eight_influences_keep_the_four_strongest() {
    // RiggedSimple with a second influence set: JOINTS_0 is accessor 1 (VEC4 USHORT), WEIGHTS_0
    // accessor 4. Vertex 0 gets influences spread over both sets, the rest an empty set 1.
    let dir = assets();
    let original = load(&dir, "RiggedSimple.glb");
    let (mut json, mut bin) = glb_parts(&std::fs::read(dir.join("RiggedSimple.glb")).unwrap());
    let j0 = element_offset(&json, 1, 0, 8);
    let w0 = element_offset(&json, 4, 0, 16);
    for (k, (j, w)) in [(0u16, 0.4f32), (1, 0.1), (0, 0.02), (1, 0.01)].iter().enumerate() {
        bin[j0 + 2 * k..j0 + 2 * k + 2].copy_from_slice(&j.to_le_bytes());
        bin[w0 + 4 * k..w0 + 4 * k + 4].copy_from_slice(&w.to_le_bytes());
    }
    let n = 160;
    let (joints_at, weights_at) = (bin.len(), bin.len() + n * 8);
    let mut joints1 = vec![0u8; n * 8];
    let mut weights1 = vec![0u8; n * 16];
    for (k, (j, w)) in [(1u16, 0.3f32), (0, 0.2), (1, 0.0), (0, 0.0)].iter().enumerate() {
        joints1[2 * k..2 * k + 2].copy_from_slice(&j.to_le_bytes());
        weights1[4 * k..4 * k + 4].copy_from_slice(&w.to_le_bytes());
    }
    bin.extend(joints1);
    bin.extend(weights1);
    json["buffers"][0]["byteLength"] = json!(bin.len());
    let views = json["bufferViews"].as_array_mut().unwrap();
    views.push(json!({ "buffer": 0, "byteOffset": joints_at, "byteLength": n * 8 }));
    views.push(json!({ "buffer": 0, "byteOffset": weights_at, "byteLength": n * 16 }));
    let view = views.len() - 2;
    let accessors = json["accessors"].as_array_mut().unwrap();
    accessors.push(json!({ "bufferView": view, "componentType": 5123, "count": n, "type": "VEC4" }));
    accessors.push(json!({ "bufferView": view + 1, "componentType": 5126, "count": n, "type": "VEC4" }));
    let first = accessors.len() - 2;
    let attributes = &mut json["meshes"][0]["primitives"][0]["attributes"];
    attributes["JOINTS_1"] = json!(first);
    attributes["WEIGHTS_1"] = json!(first + 1);

    let model = load_gltf_slice(&make_glb(&json, &bin), Path::new("Eight.glb")).unwrap();
    let prim = &model.meshes[0].primitives[0];
    let (joints, weights) = (prim.joints.as_ref().unwrap(), prim.weights.as_ref().unwrap());
    // 0.4, 0.3, 0.2 and 0.1 of the eight; 0.02 and 0.01 dropped; the sum is already 1.
    assert_eq!(joints[0], [0, 1, 0, 1]);
    for (got, want) in weights[0].iter().zip([0.4, 0.3, 0.2, 0.1]) {
        assert!((got - want).abs() < 1e-6, "{:?}", weights[0]);
    }
    assert!(
        model.warnings.iter().any(|w| w.contains("1 vertices have more than 4 influences")),
        "{:?}",
        model.warnings
    );
    // Every other vertex skins as before: the same weight per joint.
    let (joints_before, weights_before) = {
        let p = &original.meshes[0].primitives[0];
        (p.joints.as_ref().unwrap(), p.weights.as_ref().unwrap())
    };
    let per_joint = |j: &[u16; 4], w: &[f32; 4]| {
        let mut sum = [0.0f32; 2];
        for k in 0..4 {
            sum[j[k] as usize] += w[k];
        }
        sum
    };
    for v in 1..n {
        let (a, b) = (per_joint(&joints[v], &weights[v]), per_joint(&joints_before[v], &weights_before[v]));
        assert!((a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6, "vertex {v}: {a:?} vs {b:?}");
    }
}

/// Random byte damage anywhere in each asset: the loader may accept or reject, never panic.
#[test]
fn random_corruption_never_panics() {
    let dir = assets();
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut rejected = 0;
    for name in ALL {
        let original = std::fs::read(dir.join(name)).unwrap();
        for _ in 0..150 {
            let mut bytes = original.clone();
            for _ in 0..1 + next() % 8 {
                let at = (next() % bytes.len() as u64) as usize;
                bytes[at] = next() as u8;
            }
            if load_gltf_slice(&bytes, Path::new(name)).is_err() {
                rejected += 1;
            }
        }
    }
    assert!(rejected > 0);
}

/// JSON pointers of every number in `value`.
fn number_pointers(value: &Value, at: String, out: &mut Vec<String>) {
    match value {
        Value::Number(_) => out.push(at),
        Value::Array(items) => {
            for (i, v) in items.iter().enumerate() {
                number_pointers(v, format!("{at}/{i}"), out);
            }
        }
        Value::Object(map) => {
            for (k, v) in map {
                number_pointers(v, format!("{at}/{k}"), out);
            }
        }
        _ => {}
    }
}

/// Random values in the JSON (indices, offsets, lengths, counts, strides, enums, times): the
/// loader may accept or reject, never panic.
#[test]
fn random_json_numbers_never_panic() {
    let dir = assets();
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let specials = [
        json!(0),
        json!(1),
        json!(-1),
        json!(3),
        json!(5121),
        json!(5126),
        json!(65),
        json!(4_294_967_295u64),
        json!(1e300),
        json!(0.5),
    ];
    for name in ALL {
        let original = std::fs::read(dir.join(name)).unwrap();
        let (json, bin) = if name.ends_with(".glb") {
            glb_parts(&original)
        } else {
            (serde_json::from_slice(&original).unwrap(), Vec::new())
        };
        let mut pointers = Vec::new();
        number_pointers(&json, String::new(), &mut pointers);
        for _ in 0..200 {
            let mut damaged = json.clone();
            for _ in 0..1 + next() % 3 {
                let pointer = &pointers[(next() % pointers.len() as u64) as usize];
                let value = specials[(next() % specials.len() as u64) as usize].clone();
                if let Some(slot) = damaged.pointer_mut(pointer) {
                    *slot = value;
                }
            }
            let bytes =
                if name.ends_with(".glb") { make_glb(&damaged, &bin) } else { serde_json::to_vec(&damaged).unwrap() };
            let _ = load_gltf_slice(&bytes, Path::new(name));
        }
    }
}

fn encode_base64(bytes: &[u8]) -> String {
    use base64::Engine as _;
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

/// What none of the test assets has: a sparse accessor without a buffer view, normalised
/// UNSIGNED_BYTE texture coordinates, UNSIGNED_BYTE indices, a triangle fan, a CUBICSPLINE
/// channel read from a file, a camera and KHR_lights_punctual lights.
#[test]
fn synthetic_file_covers_sparse_fans_cubic_lights_and_cameras() {
    let mut bin = Vec::new();
    bin.extend_from_slice(&[0u8, 1, 2, 3]); // view 0: fan indices
    bin.extend_from_slice(&[1u8, 2, 3, 0]); // view 1: sparse indices (3 used)
    for v in [[1.0f32, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]] {
        for x in v {
            bin.extend_from_slice(&x.to_le_bytes()); // view 2: sparse values
        }
    }
    bin.extend_from_slice(&[0u8, 0, 255, 0, 255, 255, 0, 255]); // view 3: UVs
    for t in [0.0f32, 1.0] {
        bin.extend_from_slice(&t.to_le_bytes()); // view 4: key times
    }
    let keys = [[0.0f32; 3], [0.0; 3], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0; 3]];
    for v in keys {
        for x in v {
            bin.extend_from_slice(&x.to_le_bytes()); // view 5: in, value, out per key
        }
    }
    assert_eq!(bin.len(), 132);
    let view = |offset: usize, len: usize| json!({ "buffer": 0, "byteOffset": offset, "byteLength": len });
    let doc = json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": { "KHR_lights_punctual": { "lights": [
            { "type": "spot", "color": [1.0, 0.5, 0.0], "intensity": 3.0, "range": 10.0,
              "spot": { "innerConeAngle": 0.1, "outerConeAngle": 0.5 } },
            { "type": "directional" }
        ] } },
        "scene": 0,
        "scenes": [{ "nodes": [0, 1] }],
        "nodes": [
            { "mesh": 0 },
            { "camera": 0, "extensions": { "KHR_lights_punctual": { "light": 0 } } }
        ],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.1 } }],
        "meshes": [{ "primitives": [{
            "attributes": { "POSITION": 1, "TEXCOORD_0": 2, "_TEMPERATURE": 2 },
            "indices": 0,
            "mode": 6
        }] }],
        "accessors": [
            { "bufferView": 0, "componentType": 5121, "count": 4, "type": "SCALAR" },
            { "componentType": 5126, "count": 4, "type": "VEC3",
              "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0],
              "sparse": { "count": 3,
                          "indices": { "bufferView": 1, "componentType": 5121 },
                          "values": { "bufferView": 2 } } },
            { "bufferView": 3, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2" },
            { "bufferView": 4, "componentType": 5126, "count": 2, "type": "SCALAR",
              "min": [0.0], "max": [1.0] },
            { "bufferView": 5, "componentType": 5126, "count": 6, "type": "VEC3" }
        ],
        "animations": [{
            "channels": [{ "sampler": 0, "target": { "node": 0, "path": "translation" } }],
            "samplers": [{ "input": 3, "output": 4, "interpolation": "CUBICSPLINE" }]
        }],
        "bufferViews": [view(0, 4), view(4, 3), view(8, 36), view(44, 8), view(52, 8), view(60, 72)],
        "buffers": [{ "byteLength": 132,
                      "uri": format!("data:application/octet-stream;base64,{}", encode_base64(&bin)) }]
    });
    let model = load_gltf_slice(&serde_json::to_vec(&doc).unwrap(), Path::new("synthetic.gltf"))
        .unwrap_or_else(|e| panic!("{e}"));

    let prim = &model.meshes[0].primitives[0];
    let expected = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    assert_eq!(prim.positions, expected);
    assert_eq!(prim.indices, [1, 2, 0, 2, 3, 0]);
    assert_eq!(prim.source_index_width, Some(1));
    assert!(prim.normals_generated && prim.normals.iter().all(|n| *n == Vec3::Z));
    let uv = prim.uv0.as_ref().unwrap();
    assert_eq!(uv[2], glam::Vec2::ONE);
    assert!(model.warnings.iter().any(|w| w.contains("_TEMPERATURE")));

    let pose = pose_at(&model, 0, 0.5, TimeMode::Clamp).unwrap();
    assert!((pose[0].translation.x - 1.0).abs() < 1e-6, "{}", pose[0].translation);

    use crate::scene::model::{LightKind, Projection};
    assert_eq!(model.nodes[1].light, Some(0));
    assert_eq!(model.nodes[1].camera, Some(0));
    let spot = &model.lights[0];
    assert_eq!(spot.kind, LightKind::Spot { inner_cone_angle: 0.1, outer_cone_angle: 0.5 });
    assert_eq!((spot.color, spot.intensity, spot.range), (Vec3::new(1.0, 0.5, 0.0), 3.0, Some(10.0)));
    assert_eq!(model.lights[1].kind, LightKind::Directional);
    assert_eq!(model.lights[1].intensity, 1.0);
    assert_eq!(
        model.cameras[0].projection,
        Projection::Perspective { yfov: 0.8, aspect_ratio: None, znear: 0.1, zfar: None }
    );
    assert_eq!(model.roots, [0, 1]);

    // Sparse indices must increase: swapping two is an error naming the accessor.
    let mut bad = doc.clone();
    let mut bin2 = bin.clone();
    bin2[4..7].copy_from_slice(&[2, 1, 3]);
    bad["buffers"][0]["uri"] = json!(format!("data:application/octet-stream;base64,{}", encode_base64(&bin2)));
    let msg = load_gltf_slice(&serde_json::to_vec(&bad).unwrap(), Path::new("sparse.gltf")).unwrap_err().to_string();
    assert_mentions(&msg, &["sparse.gltf", "accessor 1", "strictly increasing"]);
}

#[test]
fn quantized_meshes_load_and_unsupported_required_extensions_are_refused() {
    // Box.glb rewritten as gltfpack writes KHR_mesh_quantization: positions as plain SHORTs
    // (x 10,000) undone by a node scale, normals as normalised BYTEs.
    let dir = assets();
    let tmp = TempDir::new("quantized");
    let original = load(&dir, "Box.glb");
    let (mut json, mut bin) = glb_parts(&std::fs::read(dir.join("Box.glb")).unwrap());
    let base = bin.len();
    for p in &original.meshes[0].primitives[0].positions {
        for c in p.to_array() {
            bin.extend_from_slice(&((c * 10_000.0).round() as i16).to_le_bytes());
        }
        bin.extend_from_slice(&[0, 0]); // vertex stride padded to 4 bytes
    }
    let normals_at = bin.len();
    for n in &original.meshes[0].primitives[0].normals {
        bin.extend(n.to_array().map(|c| (c * 127.0).round() as i8 as u8));
        bin.push(0);
    }
    let views = json["bufferViews"].as_array_mut().unwrap();
    views.push(json!({ "buffer": 0, "byteOffset": base, "byteLength": 24 * 8, "byteStride": 8 }));
    views.push(json!({ "buffer": 0, "byteOffset": normals_at, "byteLength": 24 * 4, "byteStride": 4 }));
    json["buffers"][0]["byteLength"] = json!(bin.len());
    json["accessors"][2] = json!({ "bufferView": 2, "componentType": 5122, "count": 24, "type": "VEC3",
        "min": [-5000, -5000, -5000], "max": [5000, 5000, 5000] });
    json["accessors"][1] =
        json!({ "bufferView": 3, "componentType": 5120, "normalized": true, "count": 24, "type": "VEC3" });
    json["nodes"][1]["scale"] = json!([1e-4, 1e-4, 1e-4]);

    // Without the extension declared, integer positions are invalid glTF.
    let msg = load_error(&tmp, "Undeclared.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["Undeclared.glb", "POSITION", "SHORT"]);

    json["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
    json["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    let path = tmp.write("Quantized.glb", &make_glb(&json, &bin));
    let model = load_gltf(&path).unwrap();
    assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    let (expected, got) = (&original.meshes[0].primitives[0], &model.meshes[0].primitives[0]);
    let scale = model.nodes[1].local.scale;
    for (a, b) in expected.positions.iter().zip(&got.positions) {
        assert!((*a - *b * scale).abs().max_element() < 1e-6, "{a} vs {b} x {scale}");
    }
    for (a, b) in expected.normals.iter().zip(&got.normals) {
        assert!(a.dot(*b) > 0.9999, "normal {a} read as {b}");
    }
    assert_eq!(expected.indices, got.indices);

    // A required extension that changes what the bytes mean is refused by name, each named once.
    json["extensionsUsed"] = json!(["KHR_mesh_quantization", "KHR_draco_mesh_compression", "EXT_unknown"]);
    json["extensionsRequired"] =
        json!(["KHR_draco_mesh_compression", "EXT_meshopt_compression", "EXT_unknown", "KHR_draco_mesh_compression"]);
    let msg = load_error(&tmp, "Draco.glb", &make_glb(&json, &bin));
    assert_mentions(&msg, &["Draco.glb", "requires extensions KHR_draco_mesh_compression, EXT_unknown,"]);
    assert_eq!(msg.matches("KHR_draco_mesh_compression").count(), 1, "{msg}");
    assert!(!msg.contains('\n'), "{msg}");
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
