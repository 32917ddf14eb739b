//! The shadow-volume family's options, as plain data and as their own flags (`clap::Args`,
//! flattened into the command line).

use clap::ArgAction;

use crate::error::Result;
use crate::technique::flags::clap_defaults;
use crate::technique::shadow_volume::alpha_counter;

crate::names::named_enum! {
    /// How volume walls are counted.
    pub enum VolumeMethod {
        /// z-fail when the camera (or its near plane) is inside a volume, else z-pass.
        #[default]
        Auto = "auto",
        ZPass = "zpass",
        ZFail = "zfail",
    }
}

crate::names::named_enum! {
    /// How the count becomes a shadow mask.
    pub enum Normalize {
        /// Seed 000's fixed-function sequence (Hall's article, docs/sources.md): N0, iterations,
        /// REVERSE_SUBTRACT D, ADD D, apply.
        #[default]
        Seed = "seed",
        /// As `seed`, with one MAX pass in place of the two D passes.
        Max = "max",
        /// One full-screen pass reading the count as an input attachment.
        Subpass = "subpass",
    }
}

crate::names::named_enum! {
    /// What the CPU does for a volume, and what the vertex shader does.
    pub enum VolumeExtrusion {
        /// Doom 3 BFG's: the CPU chooses the indices (silhouette walls and caps) when the light or
        /// the caster moved, over doubled vertices uploaded once per rigid mesh, which the vertex
        /// shader pushes away from the light.
        #[default]
        Indices = "indices",
        /// The shadow-mesh form: the vertex shader decides everything from tables built at load,
        /// so the CPU does nothing per frame, for the cost of shading every edge's candidates
        /// (skinned and mirrored casters keep `indices`).
        Shader = "shader",
    }
}

/// The shadow-volume family's options (`shadow-volume`), and its flags. How dark the shadow is
/// is `RenderOptions::shadow_tone`, shared with the planar family.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, clap::Args)]
pub struct ShadowVolumeOptions {
    // k: each volume wall adds or removes k/255 of alpha.
    /// shadow-volume: alpha added per volume wall, in 1/255 steps (1..=8).
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub increment: u8,
    /// shadow-volume: `auto` (z-fail when the camera is inside a volume), `zpass` or `zfail`.
    #[arg(id = "volume_method", long = "volume-method", value_name = "VOLUME_METHOD", value_enum, default_value_t)]
    pub method: VolumeMethod,
    /// shadow-volume: how counts become a mask.
    #[arg(long, value_enum, default_value_t)]
    pub normalize: Normalize,
    // A diagnostic pass a user asks for (docs/design/saturation.md), never part of a timed frame.
    /// shadow-volume: add the full-screen saturation probe, a diagnostic pass (`seed` and `max`
    /// count saturation only with it; `subpass` counts it in its apply, and the probe then
    /// cross-checks that count). Never part of a timed `bench` frame.
    #[arg(long)]
    pub saturation_probe: bool,
    // Volumes end just past the receivers' bounds and each is scissored to where it can shade,
    // the apply to their union, in both paths alike (docs/shadow-volumes.md, "Volumes clipped to
    // where they can shade"). Off (`--unclipped-volumes`): every volume reaches infinity over
    // the whole frame, to measure what clipping saves.
    /// shadow-volume: draw every volume whole, to infinity and over the whole frame, instead of
    /// clipped to the receivers' bounds and scissored to where it can shade (to measure what
    /// the clipping saves; the image is the same).
    #[arg(id = "unclipped_volumes", long = "unclipped-volumes", action = ArgAction::SetFalse)]
    pub clip_volumes: bool,
    // A caster wholly in the shadow of other casters, as the light sees it, casts nothing new
    // (CC Shadow Volumes' culling, made conservative: docs/shadow-volumes.md, "Casters culled").
    // Opt-in: on real assemblies it finds few casters for its CPU cost (measured there).
    /// shadow-volume: leave out, per light, the volumes of casters that lie wholly in the shadow
    /// of other casters, found on the CPU from a conservative occluder map (the image is the
    /// same; `profile` reports the casters culled and the CPU time).
    #[arg(long = "cull-casters")]
    pub cull_casters: bool,
    // In z-pass the alpha counter's two culled pipelines each draw every near cap of an open
    // caster, though the face under a near cap hides it from one of them (docs/shadow-volumes.md,
    // "Near caps under their faces"). Off (`--whole-near-caps`): both draw them all, to measure
    // what leaving them out saves.
    /// shadow-volume: in z-pass, draw every near cap of an open (two-sided) caster with both
    /// counting pipelines, instead of only with the one that can see it past its own face (to
    /// measure what that saves; the image is the same).
    #[arg(id = "whole_near_caps", long = "whole-near-caps", action = ArgAction::SetFalse)]
    pub split_near_caps: bool,
    // Both forms draw the same bytes; `bench` compares their costs.
    /// shadow-volume: `indices` (the CPU chooses each volume's indices when its light or caster
    /// moved; the vertex shader extrudes) or `shader` (the vertex shader does it all from
    /// tables built at load; no CPU work per frame, more vertex work). The image is the same.
    #[arg(id = "volume_extrusion", long = "volume-extrusion", value_name = "WHERE", value_enum, default_value_t)]
    pub extrusion: VolumeExtrusion,
    /// Draw the volumes of this caster only (its index among the frame's casters,
    /// `technique_stats.casters`): how `profile --caster-fill` measures each caster's share of
    /// the fill, frame by frame. Never set by a user.
    #[arg(skip)]
    pub only_caster: Option<u32>,
    /// Draw the volumes without their depth test, so that their passes' occlusion queries count
    /// every sample the volumes cover: how `profile` measures the area they rasterise, beside
    /// the fill counter and the samples that pass. The frame is no shadow. Never set by a user.
    #[arg(skip)]
    pub coverage_probe: bool,
    /// The device has `fragmentStoresAndAtomics` (Android Baseline 2022), so the `subpass`
    /// apply counts saturated samples with one atomic add per pixel. The renderer turns it off on a
    /// device without the feature; a plan printed without a device assumes the baseline.
    #[arg(skip = true)]
    pub fragment_atomics: bool,
}

impl Default for ShadowVolumeOptions {
    fn default() -> Self {
        clap_defaults()
    }
}

impl ShadowVolumeOptions {
    /// Checks the numbers a user typed (k in 1..=8).
    pub fn check(&self) -> Result<()> {
        alpha_counter::check_increment(self.increment).map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_are_the_flags_defaults() {
        let volumes = ShadowVolumeOptions::default();
        assert_eq!((volumes.increment, volumes.method, volumes.normalize), (1, VolumeMethod::Auto, Normalize::Seed));
        assert!(volumes.clip_volumes && volumes.split_near_caps && volumes.fragment_atomics);
        assert!(!volumes.saturation_probe);
    }
}
