//! JSON text to a validated glTF document: tolerated encoding slips, the repairs of `repair`,
//! then the gltf crate's parsing and validation with its errors made readable.

use gltf::json;
use json::validation::Validate;

use super::problem::Problem;
use super::repair;

/// JSON text to a validated glTF document.
pub(super) fn parse_json(text: &[u8], warnings: &mut Vec<String>) -> std::result::Result<json::Root, Problem> {
    // Tolerated although the spec forbids them: a UTF-8 byte order mark, and a GLB JSON chunk
    // padded with NULs instead of spaces.
    let text = text.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(text);
    let end = text.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
    let text = text.get(..end).unwrap_or(text);
    let mut value: serde_json::Value = serde_json::from_slice(text)
        .map_err(|e| format!("not a glTF file: neither GLB (no 'glTF' magic) nor valid JSON ({e})"))?;
    if !value.is_object() {
        return Err("not a glTF file: the JSON is not an object".into());
    }
    repair::integral_floats_to_integers(&mut value);
    repair::strip_extras(&mut value);
    repair::drop_channels_without_node(&mut value, warnings);
    repair::default_scene_nodes(&mut value);
    repair::strip_custom_attributes(&mut value, warnings);
    repair::accept_required_extensions(&mut value)?;
    repair::fill_missing_position_bounds(&mut value, warnings);
    repair::drop_invalid_optional_enums(&mut value, warnings);
    // Re-serialised rather than `from_value`: gltf-json keeps some extension data as raw JSON,
    // which only deserialises from text.
    let text = serde_json::to_vec(&value).map_err(|e| format!("JSON: {e}"))?;
    let root: json::Root = json::deserialize::from_slice(&text).map_err(|e| format!("not a glTF 2.0 document: {e}"))?;
    let major = root.asset.version.split('.').next().unwrap_or_default();
    if major != "2" {
        return Err(format!("glTF version {} is not supported (only 2.x)", root.asset.version));
    }
    // gltf-json's validation indexes `accessors[POSITION]` without a bounds check.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for index in prim.attributes.values() {
                if root.accessors.get(index.value()).is_none() {
                    return Err(format!(
                        "mesh {m} primitive {p}: attribute accessor {} does not exist ({} \
                         accessors)",
                        index.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    // gltf-json's validation (references in range, required fields), less what the loader
    // handles itself (`tolerated`).
    let mut errors = Vec::new();
    root.validate(&root, json::Path::new, &mut |path: &dyn Fn() -> json::Path, error| {
        let path = path().as_str().to_owned();
        if !tolerated(&path, error) {
            errors.push(format!("{path}: {error}"));
        }
    });
    if !errors.is_empty() {
        let more = errors.len().saturating_sub(5);
        let more = if more > 0 { format!(" (and {more} more)") } else { String::new() };
        errors.truncate(5);
        return Err(format!("invalid glTF: {}{more}", errors.join("; ")));
    }
    Ok(root)
}

/// Validation errors of gltf-json for things that are valid glTF and handled by the loader: an
/// accessor without a bufferView is valid (zero-filled, read by `accessors`), and a light of an
/// unknown type is skipped by `nodes`.
/// An accessor of an unknown `type` is refused when it is read, not before (an unused one is
/// harmless), and a primitive without POSITION is skipped by `meshes` with a warning.
fn tolerated(path: &str, error: json::validation::Error) -> bool {
    use json::validation::Error;
    let accessor = |field: &str| path.starts_with("accessors[") && path.ends_with(field);
    let light_type = path.starts_with("extensions.khrLightsPunctual.lights[") && path.ends_with("].type");
    let position = path.starts_with("meshes[") && path.ends_with(".attributes[\"POSITION\"]");
    match error {
        Error::Missing => accessor("].bufferView") || position,
        Error::Invalid => accessor("].type") || light_type,
        _ => false,
    }
}
