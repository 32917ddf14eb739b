//! Writing a read-back frame (`image::RgbaImage`) as PNG without ever leaving half a file.

use std::path::Path;

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

/// Writes `bytes` to `path` through a temporary file and a rename (the report crate's
/// writer), so a failure never leaves a partial file behind.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    nostencil_fillrate_report::output::write_atomically(path, bytes)
        .map_err(|source| Error::Io { path: path.to_path_buf(), source })
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
