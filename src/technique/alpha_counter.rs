//! The alpha channel as an 8-bit counter (DESIGN.md sections 1 and 2): the blend arithmetic
//! of the seed's normalisation passes, simulated on the CPU so that the number of iterations is
//! derived from the increment k, never hard-coded.

use crate::error::{Error, Result};

/// Largest increment the renderer accepts (`--increment 1..8`).
pub const MAX_INCREMENT: u8 = 8;

/// The largest volume count the counter holds with increment k: 255 / k.
pub fn capacity(k: u8) -> u32 {
    255 / k.max(1) as u32
}

pub fn check_increment(k: u8) -> Result<u8> {
    if (1..=MAX_INCREMENT).contains(&k) {
        Ok(k)
    } else {
        Err(Error::InvalidInput(format!("--increment {k}: must be 1 to {MAX_INCREMENT}")))
    }
}

/// An 8-bit blend product as lavapipe computes it (DESIGN.md section 7): `a * b / 255`,
/// rounded as `(p + (p >> 8) + 128) >> 8`.
pub fn blend_product(a: u8, b: u8) -> u8 {
    let p = a as u32 * b as u32;
    ((p + (p >> 8) + 128) >> 8) as u8
}

/// N0: `SUBTRACT, Sf = ONE_MINUS_DST_ALPHA, Df = ONE`, fragment alpha 1: `1 - 2a`.
pub fn seed_first_step(a: u8) -> u8 {
    let src = blend_product(255, 255 - a) as i32;
    (src - a as i32).clamp(0, 255) as u8
}

/// N1..: `REVERSE_SUBTRACT, Sf = ONE_MINUS_DST_ALPHA, Df = DST_ALPHA`, fragment alpha 1:
/// `a * a - (1 - a)`. 1 stays 1; any deficit grows until the pixel reaches 0.
pub fn seed_iteration(a: u8) -> u8 {
    let dst = blend_product(a, a) as i32;
    let src = blend_product(255, 255 - a) as i32;
    (dst - src).clamp(0, 255) as u8
}

/// The alpha values a count goes through: after N0, then after each iteration until 0.
pub fn seed_sequence(count_alpha: u8) -> Vec<u8> {
    let mut values = vec![seed_first_step(count_alpha)];
    while let Some(&last) = values.last() {
        if last == 0 || last == 255 || values.len() > 32 {
            break;
        }
        values.push(seed_iteration(last));
    }
    values
}

/// Iterations after N0 needed so that every non-zero count (k, 2k, ... up to 255) reaches 0,
/// while a count of 0 stays at 1.
pub fn seed_iterations(k: u8) -> Result<usize> {
    let k = check_increment(k)?;
    if seed_first_step(0) != 255 || seed_iteration(255) != 255 {
        return Err(Error::Internal("normalisation does not keep unshadowed pixels at 1".into()));
    }
    let mut needed = 0;
    for count in (k as u32..=255).step_by(k as usize) {
        let sequence = seed_sequence(count as u8);
        if sequence.last() != Some(&0) {
            return Err(Error::Internal(format!("count {count} never normalises to 0 with k = {k}")));
        }
        needed = needed.max(sequence.len() - 1);
    }
    Ok(needed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn count_of_one_follows_the_design_table() {
        // DESIGN.md: 1 -> 253 -> 249 -> 237 -> 202 -> 107 -> 0.
        assert_eq!(seed_sequence(1), vec![253, 249, 237, 202, 107, 0]);
    }

    #[test]
    fn iterations_follow_from_k() {
        // Six passes (N0 + 5) for k = 1, five for k = 2 or 4, four for k = 8.
        assert_eq!(seed_iterations(1).unwrap(), 5);
        assert_eq!(seed_iterations(2).unwrap(), 4);
        assert_eq!(seed_iterations(4).unwrap(), 4);
        assert_eq!(seed_iterations(8).unwrap(), 3);
        assert!(seed_iterations(0).is_err());
        assert!(seed_iterations(9).is_err());
    }

    #[test]
    fn blend_product_is_within_one_of_exact() {
        for a in 0..=255u32 {
            for b in 0..=255u32 {
                let exact = (a * b) as f64 / 255.0;
                assert!((blend_product(a as u8, b as u8) as f64 - exact).abs() <= 1.0);
            }
            assert_eq!(blend_product(a as u8, 255), a as u8);
        }
    }

    #[test]
    fn capacity_is_255_over_k() {
        assert_eq!(capacity(1), 255);
        assert_eq!(capacity(2), 127);
        assert_eq!(capacity(8), 31);
    }
}
