//! Files broken on purpose (truncated, out of range, cyclic, missing, corrupted at random),
//! the loader's repairs of what it can take, and synthetic files holding what no test asset
//! has: each is rejected with an error naming the problem, or loaded, never a panic.

use super::*;

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
    let data = super::super::buffers::decode_data_uri(&uri).unwrap().unwrap();
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
