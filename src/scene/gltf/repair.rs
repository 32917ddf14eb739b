//! Fixing up glTF JSON the gltf crate would refuse although the file is valid or usable:
//! integers written as floats, `extras` of any type, animation channels without a node, scenes
//! without `nodes`, custom attributes, missing POSITION bounds, invalid values of optional enums;
//! and refusing, with a clear message, files that require an extension this loader cannot honour.
//! A repair that changes what is drawn is reported as a warning.

use super::problem::Problem;

/// Extensions this loader honours when a file lists them as required; any other required
/// extension changes what the data means (compressed or transformed), so such a file is refused.
pub(super) const SUPPORTED_REQUIRED_EXTENSIONS: &[&str] = &[
    "EXT_meshopt_compression",
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_transmission",
    "KHR_materials_unlit",
    "KHR_materials_variants",
    "KHR_mesh_quantization",
    "KHR_texture_transform",
];

/// Refuses a file that requires an extension this loader does not honour, naming each once, and
/// otherwise drops `extensionsRequired`: gltf-json would refuse the extensions the loader reads
/// itself.
pub(super) fn accept_required_extensions(value: &mut serde_json::Value) -> std::result::Result<(), Problem> {
    let Some(required) = value.as_object_mut().and_then(|o| o.remove("extensionsRequired")) else {
        return Ok(());
    };
    let names = required.as_array().ok_or("extensionsRequired is not an array")?;
    let mut unsupported: Vec<&str> = Vec::new();
    for name in names {
        let name = name.as_str().ok_or("extensionsRequired holds a non-string")?;
        if !SUPPORTED_REQUIRED_EXTENSIONS.contains(&name) && !unsupported.contains(&name) {
            unsupported.push(name);
        }
    }
    if unsupported.is_empty() {
        return Ok(());
    }
    Err(format!(
        "the file requires extension{} {}, which nostencil cannot read (it reads {}); re-export without {}",
        if unsupported.len() == 1 { "" } else { "s" },
        unsupported.join(", "),
        SUPPORTED_REQUIRED_EXTENSIONS.join(", "),
        if unsupported.len() == 1 { "it" } else { "them" },
    ))
}

/// JSON has one number type, and glTF's schema allows `1.0` where an integer is expected (the
/// glTF-Validator's integer_written_as_float.gltf); serde refuses a float for an integer field.
/// Every integral float becomes an integer, which float fields accept as well.
pub(super) fn integral_floats_to_integers(value: &mut serde_json::Value) {
    match value {
        serde_json::Value::Number(n) if n.is_f64() => {
            let Some(f) = n.as_f64() else { return };
            // Exactly representable integers only (|f| < 2^53).
            if f.fract() == 0.0 && f.abs() < 9.007_199_254_740_992e15 {
                *value = if f < 0.0 { serde_json::json!(f as i64) } else { serde_json::json!(f as u64) };
            }
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(integral_floats_to_integers),
        serde_json::Value::Object(map) => map.values_mut().for_each(integral_floats_to_integers),
        _ => {}
    }
}

/// `extras` is application data of any JSON type; gltf-json (without its `extras` feature)
/// accepts only objects there. The loader never reads them, so they are removed before parsing.
pub(super) fn strip_extras(value: &mut serde_json::Value) {
    match value {
        serde_json::Value::Array(items) => items.iter_mut().for_each(strip_extras),
        serde_json::Value::Object(map) => {
            map.remove("extras");
            map.values_mut().for_each(strip_extras);
        }
        _ => {}
    }
}

/// An animation channel may leave `target.node` out when an extension (KHR_animation_pointer)
/// says what it animates; gltf-json requires the node. Such channels animate nothing this
/// renderer draws: they are dropped, with one warning per animation.
pub(super) fn drop_channels_without_node(value: &mut serde_json::Value, warnings: &mut Vec<String>) {
    let Some(animations) = value.get_mut("animations").and_then(|a| a.as_array_mut()) else { return };
    for (a, animation) in animations.iter_mut().enumerate() {
        let Some(channels) = animation.get_mut("channels").and_then(|c| c.as_array_mut()) else { continue };
        let before = channels.len();
        channels.retain(|c| c.get("target").and_then(|t| t.get("node")).is_some() || c.get("target").is_none());
        let dropped = before - channels.len();
        if dropped > 0 {
            warnings.push(format!(
                "animation {a}: {dropped} channel(s) target no node (an extension such as KHR_animation_pointer \
                 animates them) and were ignored"
            ));
        }
    }
}

/// `scene.nodes` is optional (an empty scene); gltf-json requires it.
pub(super) fn default_scene_nodes(value: &mut serde_json::Value) {
    let Some(scenes) = value.get_mut("scenes").and_then(|s| s.as_array_mut()) else { return };
    for scene in scenes {
        if let Some(map) = scene.as_object_mut() {
            map.entry("nodes").or_insert_with(|| serde_json::json!([]));
        }
    }
}

/// The spec requires `min` and `max` on POSITION accessors and gltf-json refuses a file without
/// them, but exporters do omit them, and this loader never reads them (bounds come from the
/// positions): placeholders are filled in, with a warning, instead of refusing the file.
pub(super) fn fill_missing_position_bounds(value: &mut serde_json::Value, warnings: &mut Vec<String>) {
    let positions: Vec<u64> = value
        .get("meshes")
        .and_then(|m| m.as_array())
        .into_iter()
        .flatten()
        .filter_map(|mesh| mesh.get("primitives")?.as_array())
        .flatten()
        .filter_map(|prim| prim.get("attributes")?.get("POSITION")?.as_u64())
        .collect();
    let Some(accessors) = value.get_mut("accessors").and_then(|a| a.as_array_mut()) else { return };
    let is_vec3 = |v: Option<&serde_json::Value>| {
        v.and_then(|v| v.as_array()).is_some_and(|a| a.len() == 3 && a.iter().all(|x| x.is_number()))
    };
    let mut filled = Vec::new();
    for index in positions {
        let Some(accessor) = accessors.get_mut(index as usize).and_then(|a| a.as_object_mut()) else { continue };
        if is_vec3(accessor.get("min")) && is_vec3(accessor.get("max")) {
            continue;
        }
        accessor.insert("min".into(), serde_json::json!([0.0, 0.0, 0.0]));
        accessor.insert("max".into(), serde_json::json!([0.0, 0.0, 0.0]));
        if !filled.contains(&index) {
            filled.push(index);
        }
    }
    if !filled.is_empty() {
        let list: Vec<String> = filled.iter().map(u64::to_string).collect();
        warnings.push(format!(
            "POSITION accessor(s) {} lack the min/max the spec requires; bounds are computed from the data",
            list.join(", ")
        ));
    }
}

/// Optional enum-valued fields whose invalid values gltf-json refuses, although each has a
/// default that serves as well: (where, field, valid values). Such a value is dropped, with a
/// warning, so a sampler or a buffer-view hint cannot fail a whole file.
const OPTIONAL_ENUMS: &[(&str, &str, &[&str])] = &[
    ("samplers", "magFilter", &["9728", "9729"]),
    ("samplers", "minFilter", &["9728", "9729", "9984", "9985", "9986", "9987"]),
    ("samplers", "wrapS", &["33071", "33648", "10497"]),
    ("samplers", "wrapT", &["33071", "33648", "10497"]),
    ("bufferViews", "target", &["34962", "34963"]),
    ("materials", "alphaMode", &["\"OPAQUE\"", "\"MASK\"", "\"BLEND\""]),
    ("animations/samplers", "interpolation", &["\"LINEAR\"", "\"STEP\"", "\"CUBICSPLINE\""]),
];

pub(super) fn drop_invalid_optional_enums(value: &mut serde_json::Value, warnings: &mut Vec<String>) {
    for (place, field, valid) in OPTIONAL_ENUMS {
        // "animations/samplers": the samplers of every animation.
        let mut objects: Vec<(String, &mut serde_json::Value)> = Vec::new();
        let (outer, inner) = place.split_once('/').map_or((*place, None), |(o, i)| (o, Some(i)));
        let Some(list) = value.get_mut(outer).and_then(|v| v.as_array_mut()) else { continue };
        for (i, item) in list.iter_mut().enumerate() {
            match inner {
                None => objects.push((format!("{outer}[{i}]"), item)),
                Some(inner) => {
                    if let Some(nested) = item.get_mut(inner).and_then(|v| v.as_array_mut()) {
                        for (k, object) in nested.iter_mut().enumerate() {
                            objects.push((format!("{outer}[{i}].{inner}[{k}]"), object));
                        }
                    }
                }
            }
        }
        for (path, object) in objects {
            let Some(map) = object.as_object_mut() else { continue };
            let Some(found) = map.get(*field) else { continue };
            let text = found.to_string();
            if !valid.contains(&text.as_str()) {
                map.remove(*field);
                warnings.push(format!("{path}.{field} {text} is not a valid value; the default is used"));
            }
        }
    }
}

/// Application-specific attributes (`_NAME`) are valid glTF, but gltf-json without its
/// `extras` feature rejects them; they are removed before parsing.
pub(super) fn strip_custom_attributes(value: &mut serde_json::Value, warnings: &mut Vec<String>) {
    let Some(meshes) = value.get_mut("meshes").and_then(|m| m.as_array_mut()) else {
        return;
    };
    for (m, mesh) in meshes.iter_mut().enumerate() {
        let Some(prims) = mesh.get_mut("primitives").and_then(|p| p.as_array_mut()) else {
            continue;
        };
        for (p, prim) in prims.iter_mut().enumerate() {
            let Some(attrs) = prim.get_mut("attributes").and_then(|a| a.as_object_mut()) else {
                continue;
            };
            let custom: Vec<String> = attrs.keys().filter(|k| k.starts_with('_')).cloned().collect();
            for key in custom {
                attrs.remove(&key);
                warnings.push(format!("mesh {m} primitive {p}: custom attribute {key} ignored"));
            }
        }
    }
}
