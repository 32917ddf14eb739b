//! A frame read back to the CPU: RGBA8 bytes, row-major, top row first, as an `image::RgbaImage`.

use image::RgbaImage;

use crate::error::{Error, Result};

/// Wraps read-back bytes; `pixels` must hold exactly `width * height * 4` bytes (the crate
/// alone would accept a longer buffer).
pub fn image_from_rgba8(width: u32, height: u32, pixels: Vec<u8>) -> Result<RgbaImage> {
    let len = pixels.len();
    let wrong_size = || Error::Internal(format!("read-back: {len} bytes for {width}x{height} RGBA8"));
    if len as u64 != width as u64 * height as u64 * 4 {
        return Err(wrong_size());
    }
    RgbaImage::from_raw(width, height, pixels).ok_or_else(wrong_size)
}
