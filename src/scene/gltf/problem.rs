//! The readers' error before it has a file: `load_gltf_slice` wraps it in `Error::Asset`,
//! which names the file.

/// What went wrong, without the file name: `load_gltf_slice` wraps it in `Error::Asset`.
pub(super) type Problem = String;
