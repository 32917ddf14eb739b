//! EXT_meshopt_compression: a buffer view whose bytes are meshoptimizer-encoded in another
//! buffer, decoded with meshoptimizer's own decoders (the `meshopt` crate). The view's own
//! buffer is then only a fallback (often without data) and is never read.

use std::os::raw::{c_int, c_uchar, c_void};

use serde_json::Value;

use super::problem::Problem;

pub(super) const EXTENSION: &str = "EXT_meshopt_compression";

/// The codec's densest output is about 64 bytes per input byte (a 2-bit header per 16 bytes
/// of zeros); a view claiming more than this is refused before anything is allocated.
const MAX_EXPANSION: usize = 256;
const MAX_EXPANSION_SLACK: usize = 4096;

/// The extension object of a buffer view, as the extension's schema states it.
#[derive(Debug)]
pub(super) struct Compressed {
    pub(super) buffer: usize,
    pub(super) byte_offset: usize,
    pub(super) byte_length: usize,
    pub(super) byte_stride: usize,
    pub(super) count: usize,
    mode: Mode,
    filter: Filter,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    Attributes,
    Triangles,
    Indices,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
}

fn usize_field(ext: &Value, name: &str, default: Option<usize>) -> Result<usize, Problem> {
    match ext.get(name) {
        None => default.ok_or_else(|| format!("{EXTENSION} lacks `{name}`")),
        Some(v) => v
            .as_u64()
            .and_then(|v| usize::try_from(v).ok())
            .ok_or_else(|| format!("{EXTENSION} `{name}` is {v}, not a non-negative integer")),
    }
}

/// Reads and checks the extension object of a buffer view.
pub(super) fn parse(ext: &Value) -> Result<Compressed, Problem> {
    let mode = match ext.get("mode").and_then(Value::as_str) {
        Some("ATTRIBUTES") => Mode::Attributes,
        Some("TRIANGLES") => Mode::Triangles,
        Some("INDICES") => Mode::Indices,
        other => return Err(format!("{EXTENSION} mode {other:?} is not ATTRIBUTES, TRIANGLES or INDICES")),
    };
    let filter = match ext.get("filter").map(|f| f.as_str()) {
        None | Some(Some("NONE")) => Filter::None,
        Some(Some("OCTAHEDRAL")) => Filter::Octahedral,
        Some(Some("QUATERNION")) => Filter::Quaternion,
        Some(Some("EXPONENTIAL")) => Filter::Exponential,
        Some(other) => return Err(format!("{EXTENSION} filter {other:?} is not a known filter")),
    };
    let c = Compressed {
        buffer: usize_field(ext, "buffer", None)?,
        byte_offset: usize_field(ext, "byteOffset", Some(0))?,
        byte_length: usize_field(ext, "byteLength", None)?,
        byte_stride: usize_field(ext, "byteStride", None)?,
        count: usize_field(ext, "count", None)?,
        mode,
        filter,
    };
    let stride = c.byte_stride;
    let stride_ok = match (mode, filter) {
        (Mode::Attributes, Filter::None | Filter::Exponential) => stride % 4 == 0 && (4..=256).contains(&stride),
        (Mode::Attributes, Filter::Octahedral) => stride == 4 || stride == 8,
        (Mode::Attributes, Filter::Quaternion) => stride == 8,
        (_, Filter::None) => stride == 2 || stride == 4,
        _ => return Err(format!("{EXTENSION}: filter {filter:?} is only for mode ATTRIBUTES")),
    };
    if !stride_ok {
        return Err(format!(
            "{EXTENSION}: byteStride {stride} is not allowed for mode {mode:?} with filter {filter:?}"
        ));
    }
    if mode == Mode::Triangles && c.count % 3 != 0 {
        return Err(format!("{EXTENSION}: TRIANGLES count {} is not a multiple of 3", c.count));
    }
    Ok(c)
}

/// Decodes `compressed` (the bytes the extension points at) into the view's `view_length`
/// bytes.
pub(super) fn decode(c: &Compressed, compressed: &[u8], view_length: usize) -> Result<Vec<u8>, Problem> {
    let size = c.count.checked_mul(c.byte_stride).filter(|&s| s == view_length).ok_or_else(|| {
        format!(
            "{EXTENSION}: count {} x byteStride {} does not equal the view's byteLength {view_length}",
            c.count, c.byte_stride
        )
    })?;
    if size > compressed.len().saturating_mul(MAX_EXPANSION).saturating_add(MAX_EXPANSION_SLACK) {
        return Err(format!(
            "{EXTENSION}: {size} decoded bytes from {} compressed bytes is more than the codec can produce",
            compressed.len()
        ));
    }
    // u32 words: the filters need the alignment of their 16-bit components, and every attribute
    // stride is a multiple of 4 (an index view may end on a half word, cut off below).
    let mut words = vec![0u32; size.div_ceil(4)];
    type Decoder = unsafe extern "C" fn(*mut c_void, usize, usize, *const c_uchar, usize) -> c_int;
    let decoder: Decoder = match c.mode {
        Mode::Attributes => meshopt::ffi::meshopt_decodeVertexBuffer,
        Mode::Triangles => meshopt::ffi::meshopt_decodeIndexBuffer,
        Mode::Indices => meshopt::ffi::meshopt_decodeIndexSequence,
    };
    // SAFETY: `words` holds at least `count * stride` bytes; meshoptimizer's decoders write at
    // most that, read at most `compressed.len()` bytes, and are safe on untrusted input (they
    // return nonzero on malformed data).
    let code =
        unsafe { decoder(words.as_mut_ptr().cast(), c.count, c.byte_stride, compressed.as_ptr(), compressed.len()) };
    if code != 0 {
        return Err(format!("{EXTENSION}: the {:?} data does not decode (meshoptimizer error {code})", c.mode));
    }
    let filter: Option<unsafe extern "C" fn(*mut c_void, usize, usize)> = match c.filter {
        Filter::None => None,
        Filter::Octahedral => Some(meshopt::ffi::meshopt_decodeFilterOct),
        Filter::Quaternion => Some(meshopt::ffi::meshopt_decodeFilterQuat),
        Filter::Exponential => Some(meshopt::ffi::meshopt_decodeFilterExp),
    };
    if let Some(filter) = filter {
        // SAFETY: `parse` checked the stride against the filter (4 or 8 for octahedral, 8 for
        // quaternion, a multiple of 4 for exponential); the filter rewrites exactly `count`
        // elements of `stride` bytes in place, 4-byte aligned.
        unsafe { filter(words.as_mut_ptr().cast(), c.count, c.byte_stride) };
    }
    let mut bytes: Vec<u8> = bytemuck::cast_slice(&words).to_vec();
    bytes.truncate(size);
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ext(mode: &str, stride: usize, count: usize, filter: &str) -> Value {
        serde_json::json!({"buffer": 0, "byteLength": 1, "byteStride": stride, "count": count, "mode": mode, "filter": filter})
    }

    #[test]
    fn vertices_and_indices_round_trip_through_the_codec() {
        let vertices: Vec<[f32; 3]> = (0..100).map(|i| [i as f32, (i * i) as f32 * 0.5, -(i as f32)]).collect();
        let encoded = meshopt::encode_vertex_buffer(&vertices).expect("encode");
        let c = parse(&ext("ATTRIBUTES", 12, 100, "NONE")).expect("parse");
        let decoded = decode(&c, &encoded, 1200).expect("decode");
        assert_eq!(decoded, bytemuck::cast_slice::<[f32; 3], u8>(&vertices));

        let indices: Vec<u32> = vec![0, 1, 2, 2, 1, 3, 3, 4, 5];
        let encoded = meshopt::encode_index_buffer(&indices, 6).expect("encode");
        let c = parse(&ext("TRIANGLES", 2, 9, "NONE")).expect("parse");
        let decoded = decode(&c, &encoded, 18).expect("decode");
        // The codec keeps each triangle and its winding but may rotate its corners.
        let rotated_to_min = |t: &[u32]| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
            [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        };
        let got: Vec<u32> = bytemuck::cast_slice::<u8, u16>(&decoded).iter().map(|&i| i as u32).collect();
        let got: Vec<[u32; 3]> = got.chunks_exact(3).map(rotated_to_min).collect();
        let expected: Vec<[u32; 3]> = indices.chunks_exact(3).map(rotated_to_min).collect();
        assert_eq!(got, expected);
    }

    #[test]
    fn octahedral_and_exponential_filters_decode_to_the_encoded_values() {
        let normals: Vec<[f32; 4]> = (0..40)
            .map(|i| {
                let (a, b) = (i as f32 * 0.37, i as f32 * 0.11 - 2.0);
                [a.cos() * b.cos(), a.sin() * b.cos(), b.sin(), 1.0]
            })
            .collect();
        let mut filtered = vec![[0i16; 4]; normals.len()];
        // SAFETY: `filtered` has room for `count` elements of 8 bytes; `normals` has 4 floats each.
        unsafe {
            meshopt::ffi::meshopt_encodeFilterOct(
                filtered.as_mut_ptr().cast(),
                normals.len(),
                8,
                16,
                normals.as_ptr().cast(),
            )
        };
        let encoded = meshopt::encode_vertex_buffer(&filtered).expect("encode");
        let c = parse(&ext("ATTRIBUTES", 8, normals.len(), "OCTAHEDRAL")).expect("parse");
        let decoded = decode(&c, &encoded, normals.len() * 8).expect("decode");
        for (n, d) in normals.iter().zip(bytemuck::cast_slice::<u8, [i16; 4]>(&decoded)) {
            let got = glam::Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32) / 32767.0;
            assert!(got.distance(glam::Vec3::new(n[0], n[1], n[2])) < 1e-3, "{n:?} decoded as {got}");
        }

        let values: Vec<[f32; 3]> =
            (0..40).map(|i| [i as f32 * 1.5 - 7.0, 1e-3 * i as f32, 1e4 / (i + 1) as f32]).collect();
        let mut filtered = vec![[0u32; 3]; values.len()];
        // SAFETY: as above, 12-byte elements of 3 floats.
        unsafe {
            meshopt::ffi::meshopt_encodeFilterExp(
                filtered.as_mut_ptr().cast(),
                values.len(),
                12,
                24,
                values.as_ptr().cast(),
                meshopt::ffi::meshopt_EncodeExpMode_meshopt_EncodeExpSeparate,
            )
        };
        let encoded = meshopt::encode_vertex_buffer(&filtered).expect("encode");
        let c = parse(&ext("ATTRIBUTES", 12, values.len(), "EXPONENTIAL")).expect("parse");
        let decoded = decode(&c, &encoded, values.len() * 12).expect("decode");
        for (v, d) in values.iter().zip(bytemuck::cast_slice::<u8, [f32; 3]>(&decoded)) {
            for k in 0..3 {
                assert!((v[k] - d[k]).abs() <= v[k].abs() * 1e-6, "{v:?} decoded as {d:?}");
            }
        }
    }

    #[test]
    fn bad_parameters_and_data_are_refused() {
        assert!(parse(&ext("POINTS", 4, 3, "NONE")).unwrap_err().contains("mode"));
        assert!(parse(&ext("ATTRIBUTES", 6, 3, "NONE")).unwrap_err().contains("byteStride 6"));
        assert!(parse(&ext("TRIANGLES", 4, 4, "NONE")).unwrap_err().contains("multiple of 3"));
        assert!(parse(&ext("INDICES", 4, 4, "OCTAHEDRAL")).unwrap_err().contains("only for mode ATTRIBUTES"));
        let c = parse(&ext("ATTRIBUTES", 4, 1 << 30, "NONE")).expect("parse");
        // A huge count against a few bytes is refused before allocating.
        assert!(decode(&c, &[0xa0, 0, 0, 0], 1 << 32).unwrap_err().contains("more than the codec"));
        let c = parse(&ext("ATTRIBUTES", 4, 16, "NONE")).expect("parse");
        assert!(decode(&c, &[1, 2, 3], 64).unwrap_err().contains("does not decode"));
        assert!(decode(&c, &[1, 2, 3], 60).unwrap_err().contains("does not equal"));
    }
}
