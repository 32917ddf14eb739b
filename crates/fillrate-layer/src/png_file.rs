//! A captured image written as PNG: RGB (a presented image's alpha is not shown), encoded with
//! the `png` crate and written under a temporary name, then renamed, so that a failure leaves no
//! half-written file.

use std::path::Path;

use nostencil_fillrate_report::output::write_atomically;

/// Tightly packed RGBA8 pixels, row by row from the top.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RgbaPixels {
    width: u32,
    height: u32,
    pixels: Vec<u8>,
}

impl RgbaPixels {
    /// `pixels` must hold `width` x `height` x 4 bytes.
    pub fn new(width: u32, height: u32, pixels: Vec<u8>) -> Result<Self, String> {
        if pixels.len() as u64 != u64::from(width) * u64::from(height) * 4 {
            return Err(format!("{} bytes read back for a {width}x{height} RGBA8 image", pixels.len()));
        }
        Ok(RgbaPixels { width, height, pixels })
    }

    pub fn as_raw(&self) -> &[u8] {
        &self.pixels
    }

    /// The PNG file's bytes, alpha dropped.
    pub fn encode_rgb_png(&self) -> Result<Vec<u8>, String> {
        let rgb: Vec<u8> = self.pixels.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
        let mut out = Vec::new();
        let mut encoder = png::Encoder::new(&mut out, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let encoded = encoder.write_header().and_then(|mut writer| writer.write_image_data(&rgb));
        encoded.map_err(|e| format!("PNG encoding failed: {e}"))?;
        Ok(out)
    }

    pub fn write_rgb_png(&self, path: &Path) -> Result<(), String> {
        let bytes = self.encode_rgb_png()?;
        write_atomically(path, &bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixels_of_the_wrong_size_are_refused() {
        assert!(RgbaPixels::new(2, 2, vec![0; 15]).is_err());
    }

    #[test]
    fn the_png_decodes_to_the_pixels_without_their_alpha() {
        let image = RgbaPixels::new(2, 1, vec![1, 2, 3, 4, 5, 6, 7, 8]).expect("2x1");
        let bytes = image.encode_rgb_png().expect("encoded");
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().expect("a PNG");
        let mut rgb = vec![0; reader.output_buffer_size().expect("a size")];
        let info = reader.next_frame(&mut rgb).expect("a frame");
        assert_eq!((info.width, info.height, info.color_type), (2, 1, png::ColorType::Rgb));
        assert_eq!(&rgb[..info.buffer_size()], &[1, 2, 3, 5, 6, 7]);
    }
}
