//! Writing a read-back frame (`image::RgbaImage`) as PNG without ever leaving half a file.

use std::io::Write;
use std::path::{Path, PathBuf};

use image::RgbaImage;

use crate::error::{Error, Result};

/// Writes a PNG: RGB (opaque, what a person wants to look at) unless `keep_alpha`, in which
/// case the alpha channel, the emulated stencil, is written too. The file is written under a
/// temporary name in the same folder and renamed, so a failure leaves no partial file.
pub fn write_png(image: &RgbaImage, path: &Path, keep_alpha: bool) -> Result<()> {
    write_atomically(path, &encode_png(image, keep_alpha)?)
}

pub fn encode_png(image: &RgbaImage, keep_alpha: bool) -> Result<Vec<u8>> {
    use image::ImageEncoder;
    let (data, colour) = if keep_alpha {
        (image.as_raw().clone(), image::ExtendedColorType::Rgba8)
    } else {
        let rgb: Vec<u8> = image.as_raw().chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        (rgb, image::ExtendedColorType::Rgb8)
    };
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(&data, image.width(), image.height(), colour)
        .map_err(|e| Error::InvalidInput(format!("PNG encoding failed: {e}")))?;
    Ok(out)
}

/// Writes `bytes` under a temporary name in the same folder, then renames it to `path`, so a
/// failure never leaves a partial file behind.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let io_err = |source: std::io::Error| Error::Io { path: path.to_path_buf(), source };
    let temp = temporary_sibling(path);
    let written = (|| {
        let mut file = std::fs::File::create(&temp)?;
        file.write_all(bytes)?;
        file.sync_all()
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&temp);
        return Err(io_err(e));
    }
    std::fs::rename(&temp, path).map_err(|e| {
        let _ = std::fs::remove_file(&temp);
        io_err(e)
    })
}

fn temporary_sibling(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "out.png".into());
    path.with_file_name(format!(".{name}.{}.partial", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_write_leaves_no_file() {
        let image = RgbaImage::from_pixel(2, 2, image::Rgba([255; 4]));
        let dir = std::env::temp_dir().join(format!("nostencil-png-{}", std::process::id()));
        let missing = dir.join("no-such-folder").join("x.png");
        assert!(write_png(&image, &missing, false).is_err());
        assert!(!missing.exists());
        std::fs::create_dir_all(&dir).unwrap();
        let ok = dir.join("ok.png");
        write_png(&image, &ok, true).unwrap();
        let decoded = image::open(&ok).unwrap().to_rgba8();
        assert_eq!(decoded, image);
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().ends_with(".partial"))
            .collect();
        assert!(leftovers.is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
