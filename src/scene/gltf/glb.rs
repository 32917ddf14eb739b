//! The GLB container: a binary glTF split into its JSON chunk and its BIN chunk, with every
//! chunk length checked against the file.

use super::problem::Problem;

/// The two parts of a file: its JSON text and, for GLB, the BIN chunk.
#[derive(Debug)]
pub(super) struct Container<'a> {
    pub(super) json: &'a [u8],
    pub(super) bin: Option<&'a [u8]>,
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits a file into JSON and BIN: GLB if it starts with the GLB magic, else the whole file is
/// JSON text.
pub(super) fn split_container(bytes: &[u8]) -> Result<Container<'_>, Problem> {
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

#[cfg(test)]
mod tests {
    use super::*;

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
