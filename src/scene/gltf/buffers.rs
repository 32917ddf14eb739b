//! glTF buffers and the files they name: the GLB BIN chunk, `data:` URIs, and external files
//! resolved relative to the glTF file, each checked against its declared length; and buffer
//! views, bounds-checked against their buffer.

use std::path::{Path, PathBuf};

use gltf::json;

use super::Problem;

/// Decodes standard base64 (RFC 4648, `=` padding optional).
pub(super) fn decode_base64(text: &str) -> Result<Vec<u8>, Problem> {
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
pub(super) fn decode_data_uri(uri: &str) -> Option<Result<Vec<u8>, Problem>> {
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
pub(super) fn resolve_uri(gltf_path: &Path, uri: &str) -> Result<PathBuf, Problem> {
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
pub(super) fn read_external(gltf_path: &Path, uri: &str) -> Result<Vec<u8>, Problem> {
    let file = resolve_uri(gltf_path, uri)?;
    std::fs::read(&file).map_err(|e| format!("cannot read '{uri}' ({}): {e}", file.display()))
}

/// Loads every buffer: `buffers[i]` has exactly the declared `byteLength`.
pub(super) fn load_buffers(root: &json::Root, gltf_path: &Path, bin: Option<&[u8]>) -> Result<Vec<Vec<u8>>, Problem> {
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
pub(super) fn view_bytes<'b>(root: &json::Root, buffers: &'b [Vec<u8>], index: usize) -> Result<&'b [u8], Problem> {
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
}
