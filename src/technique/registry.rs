//! The list of techniques: the only place that names them all. The command line, `passes`,
//! `bench`, `profile --compare`, `info` and the viewer read it.

use super::interface::Technique;
use crate::error::{Error, Result};

/// Every technique, in the order `info`, `--help` and the viewer's T key list them.
pub static TECHNIQUES: &[&dyn Technique] = &[
    &super::lit::Lit,
    &super::shadow_volume::ShadowVolumes,
    &super::outline::Outline,
    &super::ink::Silhouette,
    &super::ink::Toon,
    &super::legacy::Planar,
    &super::legacy::Blob,
    &super::legacy::ShadowTexture,
    &super::legacy::ShadowMap,
    &super::legacy::ShadowTextureAtlas,
];

/// The technique called `name`.
pub fn by_name(name: &str) -> Result<&'static dyn Technique> {
    TECHNIQUES
        .iter()
        .copied()
        .find(|t| t.name() == name)
        .ok_or_else(|| Error::InvalidInput(format!("unknown technique '{name}'; available: {}", names().join(", "))))
}

/// Every technique's name, in list order.
pub fn names() -> Vec<&'static str> {
    TECHNIQUES.iter().map(|t| t.name()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_and_found() {
        let mut seen = std::collections::HashSet::new();
        for technique in TECHNIQUES {
            assert!(seen.insert(technique.name()), "{} listed twice", technique.name());
            assert_eq!(by_name(technique.name()).map(|t| t.name()).ok(), Some(technique.name()));
        }
        assert!(by_name("nope").is_err());
    }
}
