//! The byte level of glTF: the GLB container, buffers (GLB chunk, data URI, external file) and
//! accessors, all with checked offsets. The gltf crate's own reader is not used: on a bad offset
//! it returns `None` (indistinguishable from a missing attribute), and it asserts or panics on
//! wrong accessor types, zero counts and short sparse data. Everything here returns a message
//! that the loader wraps in `Error::Asset` with the file name.

use std::path::{Path, PathBuf};

use gltf::json;
use json::accessor::{ComponentType, Type};

/// Accessors without a buffer view (all zeros, plus sparse values) are allocated in full; this
/// bounds what a hostile `count` can make us allocate.
const MAX_VIEWLESS_ACCESSOR_BYTES: usize = 256 << 20;

pub type Problem = String;

/// The two parts of a file: its JSON text and, for GLB, the BIN chunk.
#[derive(Debug)]
pub struct Container<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits a file into JSON and BIN: GLB if it starts with the GLB magic, else the whole file is
/// JSON text.
pub fn split_container(bytes: &[u8]) -> Result<Container<'_>, Problem> {
    if !bytes.starts_with(b"glTF") {
        return Ok(Container { json: bytes, bin: None });
    }
    let file_len = bytes.len();
    let (Some(version), Some(declared)) = (read_u32(bytes, 4), read_u32(bytes, 8)) else {
        return Err(format!("truncated GLB: {file_len} bytes, shorter than the 12-byte header"));
    };
    if version != 2 {
        return Err(format!("GLB version {version}, only version 2 is supported"));
    }
    let declared = declared as usize;
    if declared > file_len {
        return Err(format!("truncated GLB: the header says {declared} bytes but the file has {file_len}"));
    }
    let body = bytes.get(..declared).unwrap_or(bytes);
    let mut at = 12usize;
    let mut json_chunk = None;
    let mut bin_chunk = None;
    let mut index = 0;
    while at < body.len() {
        let (Some(len), Some(kind)) = (read_u32(body, at), read_u32(body, at + 4)) else {
            return Err(format!(
                "truncated GLB: chunk {index} header at byte {at} runs past the end ({} bytes)",
                body.len()
            ));
        };
        let start = at + 8;
        let end = start.checked_add(len as usize).filter(|&end| end <= body.len()).ok_or_else(|| {
            format!(
                "truncated GLB: chunk {index} claims {len} bytes from byte {start}, past the \
                     end of the {}-byte file",
                body.len()
            )
        })?;
        let data = body.get(start..end).unwrap_or_default();
        match (&kind.to_le_bytes(), index) {
            (b"JSON", 0) => json_chunk = Some(data),
            (b"JSON", _) => return Err(format!("GLB chunk {index} is a second JSON chunk")),
            (_, 0) => return Err("GLB does not start with a JSON chunk".into()),
            (b"BIN\0", 1) => bin_chunk = Some(data),
            (b"BIN\0", _) => return Err(format!("GLB chunk {index} is a second BIN chunk")),
            // Unknown chunks are to be skipped (glTF 2.0, section 4.4.3.1).
            _ => {}
        }
        // Chunks are 4-byte aligned; `end` already is for valid files.
        at = end.checked_add(3).map_or(usize::MAX, |e| e & !3);
        index += 1;
    }
    let json = json_chunk.ok_or("GLB has no JSON chunk")?;
    Ok(Container { json, bin: bin_chunk })
}

/// Decodes standard base64 (RFC 4648, `=` padding optional).
pub fn decode_base64(text: &str) -> Result<Vec<u8>, Problem> {
    fn value(c: u8) -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    }
    let trimmed = text.trim_end_matches('=');
    let mut out = Vec::with_capacity(trimmed.len() / 4 * 3 + 3);
    let mut acc = 0u32;
    let mut bits = 0u32;
    for (i, c) in trimmed.bytes().enumerate() {
        let v = value(c).ok_or_else(|| format!("invalid base64 character {:?} at {i}", c as char))?;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    if bits == 6 {
        return Err("base64 data has a dangling character".into());
    }
    Ok(out)
}

/// Bytes of a `data:` URI (base64 only). `None` if `uri` is not a data URI.
pub fn decode_data_uri(uri: &str) -> Option<Result<Vec<u8>, Problem>> {
    let rest = uri.strip_prefix("data:")?;
    Some(match rest.split_once(',') {
        Some((header, data)) if header.ends_with(";base64") => decode_base64(data),
        Some(_) => Err("data URI is not base64-encoded".into()),
        None => Err("data URI has no ',' before its data".into()),
    })
}

fn percent_decode(uri: &str) -> Result<String, Problem> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while let Some(&b) = bytes.get(i) {
        if b == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| format!("bad percent escape in URI '{uri}'"))?;
            out.push(hex);
            i += 3;
        } else {
            out.push(b);
            i += 1;
        }
    }
    String::from_utf8(out).map_err(|_| format!("URI '{uri}' is not UTF-8 after decoding"))
}

/// Resolves a relative URI against the directory of the glTF file.
pub fn resolve_uri(gltf_path: &Path, uri: &str) -> Result<PathBuf, Problem> {
    if let Some((scheme, _)) = uri.split_once("://") {
        return Err(format!(
            "URI '{uri}' uses the '{scheme}' scheme; only relative file paths and data URIs \
             are supported"
        ));
    }
    let relative = percent_decode(uri)?;
    let dir = gltf_path.parent().unwrap_or_else(|| Path::new(""));
    Ok(dir.join(relative))
}

/// Reads a file referenced by the glTF; the message names the URI and the resolved path.
pub fn read_external(gltf_path: &Path, uri: &str) -> Result<Vec<u8>, Problem> {
    let file = resolve_uri(gltf_path, uri)?;
    std::fs::read(&file).map_err(|e| format!("cannot read '{uri}' ({}): {e}", file.display()))
}

/// Loads every buffer: `buffers[i]` has exactly the declared `byteLength`.
pub fn load_buffers(root: &json::Root, gltf_path: &Path, bin: Option<&[u8]>) -> Result<Vec<Vec<u8>>, Problem> {
    let mut out = Vec::with_capacity(root.buffers.len());
    for (i, buffer) in root.buffers.iter().enumerate() {
        let declared = usize::try_from(buffer.byte_length.0)
            .map_err(|_| format!("buffer {i}: byteLength {} is too large", buffer.byte_length.0))?;
        let mut data = match buffer.uri.as_deref() {
            None => {
                let Some(bin) = bin.filter(|_| i == 0) else {
                    return Err(format!(
                        "buffer {i} has no uri and is not the GLB BIN chunk (the file has {})",
                        if bin.is_some() { "one, used by buffer 0" } else { "no BIN chunk" }
                    ));
                };
                bin.to_vec()
            }
            Some(uri) => match decode_data_uri(uri) {
                Some(decoded) => decoded.map_err(|e| format!("buffer {i}: {e}"))?,
                None => read_external(gltf_path, uri).map_err(|e| format!("buffer {i}: {e}"))?,
            },
        };
        if data.len() < declared {
            return Err(format!("buffer {i}: byteLength is {declared} but only {} bytes are present", data.len()));
        }
        // The GLB BIN chunk may carry up to 3 bytes of padding; views may not use them.
        data.truncate(declared);
        out.push(data);
    }
    Ok(out)
}

/// The bytes of buffer view `index`, bounds-checked against its buffer.
pub fn view_bytes<'b>(root: &json::Root, buffers: &'b [Vec<u8>], index: usize) -> Result<&'b [u8], Problem> {
    let view = root.buffer_views.get(index).ok_or_else(|| format!("bufferView {index} does not exist"))?;
    let buffer_index = view.buffer.value();
    let buffer =
        buffers.get(buffer_index).ok_or_else(|| format!("bufferView {index}: buffer {buffer_index} does not exist"))?;
    let offset = view.byte_offset.map_or(0, |o| o.0);
    let length = view.byte_length.0;
    let end = offset.checked_add(length);
    match end {
        Some(end) if end <= buffer.len() as u64 => {
            // Both fit in usize: they are at most buffer.len().
            buffer.get(offset as usize..end as usize).ok_or_else(|| format!("bufferView {index} is out of range"))
        }
        _ => Err(format!(
            "bufferView {index} (byteOffset {offset}, byteLength {length}) points past the end \
             of buffer {buffer_index} ({} bytes)",
            buffer.len()
        )),
    }
}

pub fn type_name(t: Type) -> &'static str {
    match t {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

pub fn component_name(c: ComponentType) -> &'static str {
    match c {
        ComponentType::I8 => "BYTE",
        ComponentType::U8 => "UNSIGNED_BYTE",
        ComponentType::I16 => "SHORT",
        ComponentType::U16 => "UNSIGNED_SHORT",
        ComponentType::U32 => "UNSIGNED_INT",
        ComponentType::F32 => "FLOAT",
    }
}

fn component_size(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

fn component_count(t: Type) -> usize {
    match t {
        Type::Scalar => 1,
        Type::Vec2 => 2,
        Type::Vec3 => 3,
        Type::Vec4 | Type::Mat2 => 4,
        Type::Mat3 => 9,
        Type::Mat4 => 16,
    }
}

/// An accessor copied out of its buffer view, with sparse substitution applied: `count`
/// elements of `components` values each, tightly packed (matrix column padding is not
/// supported, and matrices are only read as f32 MAT4).
pub struct Dense {
    pub ty: Type,
    pub component: ComponentType,
    pub normalized: bool,
    pub count: usize,
    bytes: Vec<u8>,
}

impl Dense {
    pub fn components(&self) -> usize {
        component_count(self.ty)
    }

    fn raw(&self, i: usize) -> Option<u32> {
        let size = component_size(self.component);
        let at = i.checked_mul(size)?;
        let b = self.bytes.get(at..at.checked_add(size)?)?;
        Some(match b {
            [a] => *a as u32,
            [a, b] => u16::from_le_bytes([*a, *b]) as u32,
            [a, b, c, d] => u32::from_le_bytes([*a, *b, *c, *d]),
            _ => return None,
        })
    }

    /// Component `i` (flat index) as f32, applying normalisation for integer types.
    pub fn float(&self, i: usize) -> f32 {
        let Some(raw) = self.raw(i) else { return 0.0 };
        let n = self.normalized;
        match self.component {
            ComponentType::F32 => f32::from_bits(raw),
            ComponentType::I8 if n => (raw as u8 as i8 as f32 / 127.0).max(-1.0),
            ComponentType::U8 if n => raw as f32 / 255.0,
            ComponentType::I16 if n => (raw as u16 as i16 as f32 / 32767.0).max(-1.0),
            ComponentType::U16 if n => raw as f32 / 65535.0,
            ComponentType::I8 => raw as u8 as i8 as f32,
            ComponentType::I16 => raw as u16 as i16 as f32,
            _ => raw as f32,
        }
    }

    /// Component `i` (flat index) as an unsigned integer (integer component types only).
    pub fn uint(&self, i: usize) -> u32 {
        self.raw(i).unwrap_or(0)
    }

    pub fn floats(&self) -> Vec<f32> {
        (0..self.count * self.components()).map(|i| self.float(i)).collect()
    }

    pub fn uints(&self) -> Vec<u32> {
        (0..self.count * self.components()).map(|i| self.uint(i)).collect()
    }
}

/// Copies `count` elements of `elem` bytes from `view` starting at `offset` with `stride`.
fn gather(
    view: &[u8],
    offset: usize,
    stride: usize,
    count: usize,
    elem: usize,
    out: &mut Vec<u8>,
) -> Result<(), Problem> {
    if count == 0 {
        return Ok(());
    }
    let last_start = (count - 1).checked_mul(stride).and_then(|x| x.checked_add(offset));
    let end = last_start.and_then(|x| x.checked_add(elem));
    match end {
        Some(end) if end <= view.len() => {}
        _ => {
            return Err(format!(
                "{count} elements of {elem} bytes (stride {stride}) from byteOffset {offset} run \
                 past the end of the {}-byte buffer view",
                view.len()
            ))
        }
    }
    out.reserve(count * elem);
    for k in 0..count {
        let at = offset + k * stride;
        let bytes = view.get(at..at + elem).ok_or_else(|| format!("element {k} is out of range of its buffer view"))?;
        out.extend_from_slice(bytes);
    }
    Ok(())
}

/// Copies accessor `index` into a `Dense`, checking its type against `types` and its component
/// type against `components` first. Errors say "accessor N ..." and what was expected.
pub fn read_accessor(
    root: &json::Root,
    buffers: &[Vec<u8>],
    index: usize,
    types: &[Type],
    components: &[ComponentType],
) -> Result<Dense, Problem> {
    let accessor = root.accessors.get(index).ok_or_else(|| format!("accessor {index} does not exist"))?;
    let ty = match accessor.type_ {
        json::validation::Checked::Valid(t) => t,
        json::validation::Checked::Invalid => return Err(format!("accessor {index}: bad type")),
    };
    let component = match accessor.component_type {
        json::validation::Checked::Valid(c) => c.0,
        json::validation::Checked::Invalid => return Err(format!("accessor {index}: bad componentType")),
    };
    if !types.contains(&ty) {
        let expected: Vec<_> = types.iter().map(|t| type_name(*t)).collect();
        return Err(format!("accessor {index} has type {}, expected {}", type_name(ty), expected.join(" or ")));
    }
    if !components.contains(&component) {
        let expected: Vec<_> = components.iter().map(|c| component_name(*c)).collect();
        return Err(format!(
            "accessor {index} has componentType {}, expected {}",
            component_name(component),
            expected.join(" or ")
        ));
    }
    let count = usize::try_from(accessor.count.0)
        .map_err(|_| format!("accessor {index}: count {} is too large", accessor.count.0))?;
    if count == 0 {
        return Err(format!("accessor {index} has count 0"));
    }
    if matches!(ty, Type::Mat2 | Type::Mat3) && component_size(component) < 4 {
        return Err(format!(
            "accessor {index}: {} {} matrices (column padding) are not supported",
            component_name(component),
            type_name(ty)
        ));
    }
    let elem = component_size(component) * component_count(ty);
    let fail = |e: String| format!("accessor {index}: {e}");

    let mut bytes = Vec::new();
    match accessor.buffer_view {
        Some(view_index) => {
            let view_index = view_index.value();
            let view = view_bytes(root, buffers, view_index).map_err(fail)?;
            let stride = match root.buffer_views.get(view_index).and_then(|v| v.byte_stride) {
                Some(s) if s.0 != 0 => {
                    if s.0 < elem {
                        return Err(format!(
                            "accessor {index}: bufferView {view_index} byteStride {} is smaller \
                             than the {elem}-byte element",
                            s.0
                        ));
                    }
                    s.0
                }
                _ => elem,
            };
            let offset = usize::try_from(accessor.byte_offset.map_or(0, |o| o.0))
                .map_err(|_| fail("byteOffset is too large".into()))?;
            gather(view, offset, stride, count, elem, &mut bytes)
                .map_err(|e| format!("accessor {index} in bufferView {view_index}: {e}"))?;
        }
        None => {
            let size = count.checked_mul(elem).filter(|&s| s <= MAX_VIEWLESS_ACCESSOR_BYTES).ok_or_else(|| {
                fail(format!(
                    "{count} elements without a bufferView exceed the \
                         {MAX_VIEWLESS_ACCESSOR_BYTES}-byte limit"
                ))
            })?;
            bytes = vec![0; size];
        }
    }

    if let Some(sparse) = &accessor.sparse {
        let sparse_count = usize::try_from(sparse.count.0)
            .ok()
            .filter(|&c| c >= 1 && c <= count)
            .ok_or_else(|| fail(format!("sparse count {} is not in 1..={count}", sparse.count.0)))?;
        let index_component = match sparse.indices.component_type {
            json::validation::Checked::Valid(c) => c.0,
            json::validation::Checked::Invalid => return Err(fail("bad sparse indices componentType".into())),
        };
        let index_size = component_size(index_component);
        if !matches!(index_component, ComponentType::U8 | ComponentType::U16 | ComponentType::U32) {
            return Err(fail(format!(
                "sparse indices have componentType {}, expected an unsigned type",
                component_name(index_component)
            )));
        }
        let iv = sparse.indices.buffer_view.value();
        let index_view = view_bytes(root, buffers, iv).map_err(fail)?;
        let mut index_bytes = Vec::new();
        let index_offset = usize::try_from(sparse.indices.byte_offset.0)
            .map_err(|_| fail("sparse indices byteOffset is too large".into()))?;
        gather(index_view, index_offset, index_size, sparse_count, index_size, &mut index_bytes)
            .map_err(|e| fail(format!("sparse indices: {e}")))?;
        let vv = sparse.values.buffer_view.value();
        let value_view = view_bytes(root, buffers, vv).map_err(fail)?;
        let mut value_bytes = Vec::new();
        let value_offset = usize::try_from(sparse.values.byte_offset.0)
            .map_err(|_| fail("sparse values byteOffset is too large".into()))?;
        gather(value_view, value_offset, elem, sparse_count, elem, &mut value_bytes)
            .map_err(|e| fail(format!("sparse values: {e}")))?;
        let indices = Dense {
            ty: Type::Scalar,
            component: index_component,
            normalized: false,
            count: sparse_count,
            bytes: index_bytes,
        };
        let mut previous: Option<usize> = None;
        for k in 0..sparse_count {
            let target = indices.uint(k) as usize;
            if target >= count || previous.is_some_and(|p| target <= p) {
                return Err(fail(format!(
                    "sparse index {k} is {target}: sparse indices must be strictly increasing \
                     and below the count {count}"
                )));
            }
            previous = Some(target);
            let (Some(dst), Some(src)) =
                (bytes.get_mut(target * elem..(target + 1) * elem), value_bytes.get(k * elem..(k + 1) * elem))
            else {
                return Err(fail(format!("sparse element {k} is out of range")));
            };
            dst.copy_from_slice(src);
        }
    }

    Ok(Dense { ty, component, normalized: accessor.normalized, count, bytes })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips_known_values() {
        assert_eq!(decode_base64("").unwrap(), b"");
        assert_eq!(decode_base64("Zg==").unwrap(), b"f");
        assert_eq!(decode_base64("Zm8=").unwrap(), b"fo");
        assert_eq!(decode_base64("Zm9v").unwrap(), b"foo");
        assert_eq!(decode_base64("Zm9vYmFy").unwrap(), b"foobar");
        assert_eq!(decode_base64("AAAB").unwrap(), [0, 0, 1]);
        assert!(decode_base64("Zm9v!").is_err());
        assert!(decode_base64("Z").is_err());
    }

    #[test]
    fn data_uris() {
        assert_eq!(decode_data_uri("data:application/octet-stream;base64,Zm9v").unwrap().unwrap(), b"foo");
        assert!(decode_data_uri("data:text/plain,foo").unwrap().is_err());
        assert!(decode_data_uri("foo.bin").is_none());
    }

    #[test]
    fn uris_resolve_relative_to_the_file() {
        let p = resolve_uri(Path::new("/a/b/model.gltf"), "tex%20ture/x.png").unwrap();
        assert_eq!(p, Path::new("/a/b/tex ture/x.png"));
        assert!(resolve_uri(Path::new("m.gltf"), "https://example.com/x.bin").is_err());
        assert!(resolve_uri(Path::new("m.gltf"), "bad%zz").is_err());
    }

    #[test]
    fn glb_header_checks() {
        assert!(split_container(b"glTF\x02\0\0").unwrap_err().contains("12-byte header"));
        let mut glb = b"glTF".to_vec();
        glb.extend_from_slice(&2u32.to_le_bytes());
        glb.extend_from_slice(&100u32.to_le_bytes());
        assert!(split_container(&glb).unwrap_err().contains("header says 100"));
        let mut v1 = b"glTF".to_vec();
        v1.extend_from_slice(&1u32.to_le_bytes());
        v1.extend_from_slice(&12u32.to_le_bytes());
        assert!(split_container(&v1).unwrap_err().contains("version 1"));
    }
}
