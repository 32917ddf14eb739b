//! Output paths checked before any work is done.

use std::path::Path;

use crate::error::{Error, Result};

/// Refuses an output path whose folder does not exist before any rendering is done.
pub fn check_output_path(path: &Path) -> Result<()> {
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    if !parent.is_dir() {
        return Err(Error::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "the output folder does not exist"),
        });
    }
    if path.is_dir() {
        return Err(Error::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(std::io::ErrorKind::InvalidInput, "the output path is a folder"),
        });
    }
    // Outputs are written to a temporary file and renamed over the path: a device or a pipe
    // there (/dev/null) would be replaced by a plain file.
    if path.exists() && !path.is_file() {
        return Err(Error::Io {
            path: path.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "the output path is not a regular file (a device or a pipe); outputs replace their file",
            ),
        });
    }
    Ok(())
}
