//! The sRGB transfer function (IEC 61966-2-1). The frame stores sRGB-encoded colour; shaders and
//! blending work in linear light. A colour a user gives in 8-bit bytes (`--outline-colour`, a
//! colour picker's value) is sRGB-encoded and must be decoded before a shader writes it, so that
//! the picture shows those very bytes.

/// An 8-bit sRGB value as linear light in [0, 1].
pub fn decode(encoded: u8) -> f32 {
    let c = encoded as f32 / 255.0;
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear light in [0, 1] (clamped) as the nearest 8-bit sRGB value.
pub fn encode(linear: f32) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let encoded = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (encoded * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_byte_round_trips_and_known_values_hold() {
        assert!((0..=255u8).all(|b| encode(decode(b)) == b));
        assert_eq!(encode(0.5), 188);
        // The grey: linear 0.2159 is sRGB 128.
        assert_eq!(encode(0.2159), 128);
        assert_eq!((decode(128) * 10_000.0).round(), 2159.0);
        assert_eq!((encode(0.0), encode(1.0)), (0, 255));
    }
}
