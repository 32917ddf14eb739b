//! Memory traffic of one render pass on two kinds of GPU, after Mesa turnip's own model
//! (src/freedreno/vulkan/tu_pass.cc, `tu_render_pass_bandwidth_config`, and tu_autotune.cc, which
//! adds the draws' traffic as samples passed x bytes per sample before choosing GMEM or sysmem):
//! - a tile-based GPU (turnip's "gmem" figure) moves an attachment's bytes per pixel (texel bytes
//!   x samples) once when it is loaded and once when it is stored; resolves write the one-sample
//!   image from tile memory (a store of the resolve attachment). Draws stay in tile memory.
//! - an immediate-mode GPU (turnip's "sysmem" figure) writes every sample of a cleared attachment,
//!   reads every sample and writes one for a resolve, and for every sample that passes reads and
//!   writes each colour and depth/stencil attachment. Turnip adds colour once (twice with
//!   blending) and depth once per test and once per write; this model takes the upper bound,
//!   read and written, since the layer does not see the pipelines' blend and depth state.

use serde::{Deserialize, Serialize};

/// Bytes one render pass (or frame) moves to and from main memory.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Bandwidth {
    /// A tile-based GPU: loads, stores and resolves only.
    pub tiler_bytes: u64,
    /// An immediate-mode GPU: clears, resolves, and every passing sample read and written.
    pub immediate_bytes: u64,
}

impl std::ops::Add for Bandwidth {
    type Output = Bandwidth;
    fn add(self, other: Bandwidth) -> Bandwidth {
        Bandwidth {
            tiler_bytes: self.tiler_bytes + other.tiler_bytes,
            immediate_bytes: self.immediate_bytes + other.immediate_bytes,
        }
    }
}

impl std::iter::Sum for Bandwidth {
    fn sum<I: Iterator<Item = Bandwidth>>(iter: I) -> Bandwidth {
        iter.fold(Bandwidth::default(), |a, b| a + b)
    }
}

/// What the model needs of one attachment over the render area.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AttachmentCost {
    /// Bytes the load and store ops move over the render area (every sample): the tiler's figure.
    pub tile_bytes: u64,
    /// Bytes a CLEAR writes over the render area (every sample, the cleared aspects only).
    pub cleared_bytes: u64,
    /// Bytes of one sample (all aspects).
    pub bytes_per_sample: u64,
    /// A resolve destination: the samples per pixel of the image resolved into it.
    pub resolve_of: Option<u32>,
    /// Drawn into (colour, depth or stencil): every passing sample reads and writes it.
    pub drawn: bool,
}

/// The pass's traffic over `pixels` render-area pixels with `samples_passed` samples passing.
pub fn pass_bandwidth(attachments: &[AttachmentCost], pixels: u64, samples_passed: u64) -> Bandwidth {
    let fixed = fixed_bandwidth(attachments, pixels);
    Bandwidth {
        tiler_bytes: fixed.tiler_bytes,
        immediate_bytes: fixed.immediate_bytes + samples_passed * bytes_per_passing_sample(attachments),
    }
}

/// What the pass moves whatever its draws do: loads, stores and resolves on a tiler; clears and
/// resolves on an immediate-mode GPU.
pub fn fixed_bandwidth(attachments: &[AttachmentCost], pixels: u64) -> Bandwidth {
    let tiler_bytes = attachments.iter().map(|a| a.tile_bytes).sum();
    let immediate_bytes = attachments
        .iter()
        .map(|a| {
            // The resolve reads every source sample and writes the one-sample texel.
            let resolve = a.resolve_of.map_or(0, |n| pixels * a.bytes_per_sample * (n as u64 + 1));
            a.cleared_bytes + resolve
        })
        .sum();
    Bandwidth { tiler_bytes, immediate_bytes }
}

/// Bytes an immediate-mode GPU reads and writes for each sample that passes: every drawn
/// attachment's sample, read and written (a tiler keeps them in tile memory: 0).
pub fn bytes_per_passing_sample(attachments: &[AttachmentCost]) -> u64 {
    attachments.iter().filter(|a| a.drawn).map(|a| 2 * a.bytes_per_sample).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attachment(bytes: u64, samples: u64, tile_ops: u64, cleared: bool) -> AttachmentCost {
        AttachmentCost {
            tile_bytes: tile_ops * bytes * samples * 100,
            cleared_bytes: if cleared { bytes * samples * 100 } else { 0 },
            bytes_per_sample: bytes,
            resolve_of: None,
            drawn: true,
        }
    }

    #[test]
    fn samples_stay_in_tile_memory_but_not_in_an_immediate_gpu() {
        // 10x10 pixels; colour RGBA8 cleared and stored, depth D32 cleared and dropped.
        let one = [attachment(4, 1, 1, true), attachment(4, 1, 0, true)];
        let one = pass_bandwidth(&one, 100, 150);
        assert_eq!(one.tiler_bytes, 400);
        assert_eq!(one.immediate_bytes, 400 + 400 + 150 * 16);
        // The same frame at 4x: both attachments dropped, the colour resolved in the pass.
        let resolve = AttachmentCost {
            tile_bytes: 400,
            cleared_bytes: 0,
            bytes_per_sample: 4,
            resolve_of: Some(4),
            drawn: false,
        };
        let four = [attachment(4, 4, 0, true), attachment(4, 4, 0, true), resolve];
        let four = pass_bandwidth(&four, 100, 600);
        assert_eq!(four.tiler_bytes, one.tiler_bytes);
        assert_eq!(four.immediate_bytes, 1600 + 1600 + 100 * 4 * 5 + 600 * 16);
    }
}
