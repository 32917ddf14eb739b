//! What the families' flags share: their defaults taken from the flags themselves, and the
//! colour parser.

use crate::error::{Error, Result};

/// What a family's options are when no flag is given: its `Default`. The defaults are written
/// once, on the flags of its `clap::Args` struct (where `--help` shows them).
pub(crate) fn clap_defaults<T: clap::Args + clap::FromArgMatches>() -> T {
    let command = T::augment_args(clap::Command::new("defaults").no_binary_name(true));
    match command.try_get_matches_from(std::iter::empty::<&str>()).and_then(|m| T::from_arg_matches(&m)) {
        Ok(options) => options,
        // The flags' own defaults, not user input: a unit test parses each family's.
        Err(e) => panic!("the defaults of {} do not parse: {e}", std::any::type_name::<T>()),
    }
}

/// Parses an 8-bit RGB colour written `#RRGGBB` (the `#` optional) for the option `what`.
pub fn parse_rgb_hex(what: &str, text: &str) -> Result<[u8; 3]> {
    let bad = || Error::InvalidInput(format!("{what} '{text}': expected #RRGGBB, six hex digits such as #FFA000"));
    let digits = text.trim().strip_prefix('#').unwrap_or(text.trim());
    if digits.len() != 6 || !digits.chars().all(|c| c.is_ascii_hexdigit()) {
        return Err(bad());
    }
    let byte = |i: usize| u8::from_str_radix(&digits[i..i + 2], 16).map_err(|_| bad());
    Ok([byte(0)?, byte(2)?, byte(4)?])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb_hex_parses_six_digits_and_names_bad_input() {
        assert_eq!(parse_rgb_hex("--c", "#FFa000").ok(), Some([255, 160, 0]));
        assert_eq!(parse_rgb_hex("--c", "0a141e").ok(), Some([10, 20, 30]));
        for bad in ["", "#", "#FFF", "#FFA0000", "#GG0000", "red", "#+1+2+3", "#ÿÿÿ"] {
            let error = parse_rgb_hex("--c", bad).err().map(|e| e.to_string()).unwrap_or_default();
            assert!(error.contains("--c") && error.contains("#RRGGBB"), "{bad:?}: {error}");
        }
    }
}
