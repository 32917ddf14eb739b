//! glTF buffers and the files they name: the GLB BIN chunk, `data:` URIs, and external files
//! resolved relative to the glTF file, each checked against its declared length and loaded only
//! when something read needs it; and buffer views, bounds-checked against their buffer or
//! decoded from EXT_meshopt_compression.

use std::borrow::Cow;
use std::cell::{Cell, OnceCell, RefCell};
use std::path::{Path, PathBuf};

use base64::alphabet;
use base64::engine::general_purpose::{GeneralPurpose, GeneralPurposeConfig};
use base64::engine::DecodePaddingMode;
use base64::Engine as _;
use gltf::json;
use percent_encoding::percent_decode_str;

use super::meshopt;
use super::problem::Problem;

/// Standard base64 as exporters write it in data URIs: the unused low bits of the last
/// character are not checked, and padding is stripped before decoding, so any amount of it (none
/// included) is accepted.
const DATA_URI_BASE64: GeneralPurpose = GeneralPurpose::new(
    &alphabet::STANDARD,
    GeneralPurposeConfig::new()
        .with_decode_padding_mode(DecodePaddingMode::RequireNone)
        .with_decode_allow_trailing_bits(true),
);

/// Decodes standard base64 (RFC 4648, `=` padding optional).
fn decode_base64(text: &str) -> Result<Vec<u8>, Problem> {
    DATA_URI_BASE64.decode(text.trim_end_matches('=')).map_err(|e| format!("invalid base64 data: {e}"))
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

/// Decodes the percent escapes of a relative URI. A `%` not followed by two hex digits is an
/// error (a plain percent decoder would keep it as it is and look for a file of that name).
fn percent_decode(uri: &str) -> Result<String, Problem> {
    let bytes = uri.as_bytes();
    let well_formed = bytes
        .iter()
        .enumerate()
        .filter(|(_, &b)| b == b'%')
        .all(|(i, _)| bytes.get(i + 1..i + 3).is_some_and(|hex| hex.iter().all(u8::is_ascii_hexdigit)));
    if !well_formed {
        return Err(format!("bad percent escape in URI '{uri}'"));
    }
    percent_decode_str(uri)
        .decode_utf8()
        .map(Cow::into_owned)
        .map_err(|_| format!("URI '{uri}' is not UTF-8 after decoding"))
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

/// The file's buffers, each read (or decoded) on first use only: a buffer that no accessor or
/// image that is read refers to is never loaded, so a bad or missing URI there is no error. The
/// same goes for the fallback buffer of an EXT_meshopt_compression view, which is decoded from
/// another buffer instead.
pub(super) struct Buffers<'a> {
    root: &'a json::Root,
    gltf_path: &'a Path,
    bin: Option<&'a [u8]>,
    buffers: Vec<OnceCell<Result<Vec<u8>, Problem>>>,
    /// Decoded EXT_meshopt_compression views, by view index.
    decoded: Vec<OnceCell<Result<Vec<u8>, Problem>>>,
    /// Bytes left for zero-filled accessors (no bufferView), see `zeroed`.
    zero_budget: Cell<usize>,
    /// The whole budget, for messages.
    zero_limit: usize,
    /// Bytes of the file and of every buffer loaded or decoded since (see `READ_PER_BYTE`).
    held: Cell<usize>,
    /// Accessor bytes read so far (see `charge_read`).
    read: Cell<usize>,
    /// What loading repaired, for the model's warnings (see `take_warnings`).
    warnings: RefCell<Vec<String>>,
}

/// Accessors without a buffer view are zeros (plus sparse values) that the file does not store;
/// all of them together may take at most this much memory, so that a hostile `count` in a tiny
/// file cannot make the loader allocate gigabytes. 64 MiB is 5.5 million VEC3 float vertices:
/// more than any sparse-only mesh a renderer of this class will meet.
pub(super) const MAX_ZERO_FILLED_BYTES: usize = 64 << 20;

/// Below that cap, what a file may ask for is tied to its size: `ZERO_FILL_FLOOR` plus
/// `ZERO_FILL_PER_BYTE` bytes per byte of the file. Every zero-filled byte grows about sevenfold
/// on its way to a scene (f32 values, vertices, normals, indices), so without this a 250-byte
/// file with `count: 3000000` and no bufferView cost 250 MB before it was drawn or refused
/// (found by tests/inside/fuzz_gltf.rs). 1 MiB is 87,000 VEC3 float vertices of zeros.
const ZERO_FILL_FLOOR: usize = 1 << 20;
const ZERO_FILL_PER_BYTE: usize = 4;

/// Accessor data copied out of the buffers, all reads together, is tied to the data the file
/// holds: `READ_FLOOR` plus `READ_PER_BYTE` bytes per byte of the file and of the buffers it
/// loaded (external, data URIs, meshopt-decoded). A valid file reads each accessor about once
/// (a few times where primitives share one); without a bound, 300 primitives naming the same
/// 100 kB accessors in a 130 kB file cost 85 MB, and 10,000 of them gigabytes (found by
/// tests/inside/fuzz_gltf.rs).
const READ_FLOOR: usize = 4 << 20;
const READ_PER_BYTE: usize = 16;

/// The zero-filled bytes a file of `file_len` bytes may ask for.
pub(super) fn zero_fill_budget(file_len: usize) -> usize {
    file_len.saturating_mul(ZERO_FILL_PER_BYTE).saturating_add(ZERO_FILL_FLOOR).min(MAX_ZERO_FILLED_BYTES)
}

impl<'a> Buffers<'a> {
    /// `file_len` (the bytes of the glTF or GLB file) sets the zero-fill budget.
    pub(super) fn new(root: &'a json::Root, gltf_path: &'a Path, bin: Option<&'a [u8]>, file_len: usize) -> Self {
        Buffers {
            root,
            gltf_path,
            bin,
            buffers: root.buffers.iter().map(|_| OnceCell::new()).collect(),
            decoded: root.buffer_views.iter().map(|_| OnceCell::new()).collect(),
            zero_budget: Cell::new(zero_fill_budget(file_len)),
            zero_limit: zero_fill_budget(file_len),
            held: Cell::new(file_len),
            read: Cell::new(0),
            warnings: RefCell::new(Vec::new()),
        }
    }

    /// Buffer `index`, exactly its declared `byteLength`, loaded on first use.
    pub(super) fn buffer(&self, index: usize) -> Result<&[u8], Problem> {
        let cell = self.buffers.get(index).ok_or_else(|| format!("buffer {index} does not exist"))?;
        cell.get_or_init(|| self.load(index)).as_deref().map_err(Clone::clone)
    }

    fn load(&self, i: usize) -> Result<Vec<u8>, Problem> {
        let buffer = self.root.buffers.get(i).ok_or_else(|| format!("buffer {i} does not exist"))?;
        let declared = usize::try_from(buffer.byte_length.0)
            .map_err(|_| format!("buffer {i}: byteLength {} is too large", buffer.byte_length.0))?;
        let mut data = match buffer.uri.as_deref() {
            None => match self.bin.filter(|_| i == 0) {
                Some(bin) => bin.to_vec(),
                None => {
                    // Valid to the validator (the schema makes `uri` optional), but the bytes are
                    // nowhere: read as zeros, like an accessor without a buffer view, and say so.
                    let zeros = self.zeroed(declared).map_err(|e| format!("buffer {i} has no uri: {e}"))?;
                    self.warnings.borrow_mut().push(format!(
                        "buffer {i} has no uri and is not the GLB BIN chunk (the file has {}): its {declared} \
                         bytes are not in the file and are read as zeros",
                        if self.bin.is_some() { "one, used by buffer 0" } else { "no BIN chunk" }
                    ));
                    zeros
                }
            },
            Some(uri) => match decode_data_uri(uri) {
                Some(decoded) => decoded.map_err(|e| format!("buffer {i}: {e}"))?,
                None => read_external(self.gltf_path, uri).map_err(|e| format!("buffer {i}: {e}"))?,
            },
        };
        if data.len() < declared {
            return Err(format!("buffer {i}: byteLength is {declared} but only {} bytes are present", data.len()));
        }
        // The GLB BIN chunk may carry up to 3 bytes of padding; views may not use them.
        data.truncate(declared);
        if buffer.uri.is_some() {
            self.held.set(self.held.get().saturating_add(data.len()));
        }
        Ok(data)
    }

    /// The bytes of buffer view `index`: a bounds-checked slice of its buffer, or its
    /// EXT_meshopt_compression data decoded.
    pub(super) fn view(&self, index: usize) -> Result<&[u8], Problem> {
        let view = self.root.buffer_views.get(index).ok_or_else(|| format!("bufferView {index} does not exist"))?;
        if let Some(ext) = view.extensions.as_ref().and_then(|e| e.others.get(meshopt::EXTENSION)) {
            let cell = self.decoded.get(index).ok_or_else(|| format!("bufferView {index} does not exist"))?;
            let decoded = cell.get_or_init(|| {
                let here = |e: Problem| format!("bufferView {index}: {e}");
                let compressed = meshopt::parse(ext).map_err(here)?;
                let who = format!("bufferView {index}: {} data", meshopt::EXTENSION);
                let bytes = self.range(&who, compressed.buffer, compressed.byte_offset, compressed.byte_length)?;
                let length = usize::try_from(view.byte_length.0).map_err(|_| here("byteLength is too large".into()))?;
                let decoded = meshopt::decode(&compressed, bytes, length).map_err(here)?;
                self.held.set(self.held.get().saturating_add(decoded.len()));
                Ok(decoded)
            });
            return decoded.as_deref().map_err(Clone::clone);
        }
        let offset = view.byte_offset.map_or(0, |o| o.0);
        let (offset, length) = match (usize::try_from(offset), usize::try_from(view.byte_length.0)) {
            (Ok(offset), Ok(length)) => (offset, length),
            _ => return Err(format!("bufferView {index}: byteOffset or byteLength is too large")),
        };
        self.range(&format!("bufferView {index}"), view.buffer.value(), offset, length)
    }

    /// `length` bytes of buffer `buffer` from `offset`, bounds-checked; errors start with `who`.
    fn range(&self, who: &str, buffer: usize, offset: usize, length: usize) -> Result<&[u8], Problem> {
        let bytes = self.buffer(buffer).map_err(|e| format!("{who}: {e}"))?;
        offset.checked_add(length).and_then(|end| bytes.get(offset..end)).ok_or_else(|| {
            format!(
                "{who} (byteOffset {offset}, byteLength {length}) points past the end of buffer {buffer} ({} bytes)",
                bytes.len()
            )
        })
    }

    /// What loading the buffers repaired, once.
    pub(super) fn take_warnings(&self) -> Vec<String> {
        std::mem::take(&mut *self.warnings.borrow_mut())
    }

    /// Takes `size` bytes of accessor data (about to be copied) from the file's read budget
    /// (`READ_PER_BYTE`), before anything is allocated.
    pub(super) fn charge_read(&self, size: usize) -> Result<(), Problem> {
        let held = self.held.get();
        let limit = held.saturating_mul(READ_PER_BYTE).saturating_add(READ_FLOOR);
        let total = self.read.get().saturating_add(size);
        if total > limit {
            return Err(format!(
                "reading {size} more bytes of accessor data would make {total} bytes read from a file holding \
                 {held} bytes of data; the limit is 4 MiB plus {READ_PER_BYTE} times the data, i.e. {limit} \
                 (accessors read over and over, e.g. by many primitives naming the same ones)"
            ));
        }
        self.read.set(total);
        Ok(())
    }

    /// `size` zero bytes for an accessor without a buffer view, taken from the file's budget
    /// (`zero_fill_budget`).
    pub(super) fn zeroed(&self, size: usize) -> Result<Vec<u8>, Problem> {
        let left = self.zero_budget.get();
        if size > left {
            return Err(format!(
                "{size} bytes of zero-filled data (no bufferView) exceed what is left of this file's \
                 {}-byte limit for such accessors ({left} bytes; the limit is 1 MiB plus 4 bytes per byte of \
                 the file, at most {MAX_ZERO_FILLED_BYTES})",
                self.zero_limit
            ));
        }
        self.zero_budget.set(left - size);
        Ok(vec![0; size])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_fill_and_read_budgets_grow_with_the_file() {
        assert_eq!(zero_fill_budget(0), 1 << 20);
        assert_eq!(zero_fill_budget(1000), (1 << 20) + 4000);
        assert_eq!(zero_fill_budget(usize::MAX), MAX_ZERO_FILLED_BYTES);
        let root = json::Root::default();
        let buffers = Buffers::new(&root, Path::new("x.gltf"), None, 1000);
        let limit = READ_FLOOR + 16 * 1000;
        assert!(buffers.charge_read(limit - 10).is_ok());
        assert!(buffers.charge_read(10).is_ok());
        let refused = buffers.charge_read(1).unwrap_err();
        assert!(refused.contains(&format!("i.e. {limit}")), "{refused}");
    }

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
        // Lenient where exporters are: padding absent or excess, unused low bits set.
        assert_eq!(decode_base64("Zg").unwrap(), b"f");
        assert_eq!(decode_base64("Zm9v==").unwrap(), b"foo");
        assert_eq!(decode_base64("Zh==").unwrap(), b"f");
        assert!(decode_base64("Zm=9v").is_err());
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
        assert!(resolve_uri(Path::new("m.gltf"), "bad%2").is_err());
        assert!(resolve_uri(Path::new("m.gltf"), "not%FFutf8.bin").is_err());
    }

    #[test]
    fn percent_encoded_file_names_decode() {
        let p = resolve_uri(Path::new("dir/model.gltf"), "my%20buffer.bin").unwrap();
        assert_eq!(p, Path::new("dir/my buffer.bin"));
        let p = resolve_uri(Path::new("model.gltf"), "caf%C3%A9%2Btex.png").unwrap();
        assert_eq!(p, Path::new("café+tex.png"));
        // Decoded once: an escaped percent stays a percent.
        let p = resolve_uri(Path::new("model.gltf"), "100%2541.bin").unwrap();
        assert_eq!(p, Path::new("100%41.bin"));
    }
}
