//! Fixing up glTF JSON the gltf crate would refuse although the file is usable: custom
//! attributes, missing POSITION bounds, invalid values of optional enums; and refusing, with a
//! clear message, files that require an extension this loader cannot honour. Every repair is
//! reported as a warning.

use super::Problem;

/// Extensions this loader honours when a file lists them as required; any other required
/// extension changes what the data means (compressed or transformed), so such a file is refused.
pub(super) const SUPPORTED_REQUIRED_EXTENSIONS: &[&str] = &["KHR_lights_punctual", "KHR_mesh_quantization"];

/// Refuses a file that requires an extension this loader does not honour, naming it, and
/// otherwise drops `extensionsRequired`: gltf-json would refuse KHR_mesh_quantization, which
/// the loader itself reads.
pub(super) fn accept_required_extensions(value: &mut serde_json::Value) -> std::result::Result<(), Problem> {
    let Some(required) = value.as_object_mut().and_then(|o| o.remove("extensionsRequired")) else {
        return Ok(());
    };
    let names = required.as_array().ok_or("extensionsRequired is not an array")?;
    let unsupported: Vec<&str> = names
        .iter()
        .map(|n| n.as_str().ok_or("extensionsRequired holds a non-string"))
        .collect::<std::result::Result<Vec<_>, _>>()?
        .into_iter()
        .filter(|e| !SUPPORTED_REQUIRED_EXTENSIONS.contains(e))
        .collect();
    if unsupported.is_empty() {
        return Ok(());
    }
    Err(format!(
        "the file requires extension{} {}, which nostencil cannot read (it reads {}); re-export without {}",
        if unsupported.len() == 1 { "" } else { "s" },
        unsupported.join(", "),
        SUPPORTED_REQUIRED_EXTENSIONS.join(" and "),
        if unsupported.len() == 1 { "it" } else { "them" },
    ))
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
