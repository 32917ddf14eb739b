//! Shadow textures baked into an atlas page, a tile per model (seed 004,
//! docs/design/shadow-atlas.md), and the plain shadow map they are compared with.
//!
//! Pre-pass (outside the frame's render pass, skipped when neither lights nor models moved):
//! 1. shadow maps: per shadowing light, casters from it, depth only, into its layer of one
//!    depth array stored for sampling (`maps` decides which lights get one);
//! 2. (atlas) every model's shadow texture is a tile of one page (`page`): light i's
//!    visibility in channel i (R, G, B: up to 3 lights), compared against every light's map
//!    (hardware compare, slope-scaled bias). Only the tiles that can have changed are re-baked
//!    (`rebake`). A geometry image's tile is baked by its texels, each from the surface point
//!    it holds (`texel_surface`); other meshes are drawn at their atlas UVs into their tile of
//!    a raw page, then dilated (texels no triangle covered take their nearest chart's value);
//! 3. (atlas) mips: one blit chain for the page.
//!
//! Frame: the scene lit with Lambert + ambient, each light's Lambert term scaled by its
//! channel of the model's shadow texture (sampled trilinearly) or by its map's compare.
//!
//! Files: `passes` (pipelines and the plan), `maps` (which lights get a map layer and a baked
//! channel), `light` (fitting each light's view), `atlas` (each mesh's UV layout), `page` (the
//! tiles' packing), `texel_surface`, `page_targets` (the page and its passes), `rebake` and `bake_cache` (what is re-baked),
//! `atlas_vertices` (the meshes' vertices in their atlases, posed),
//! `bake` (the projective texture's per-model bake, copy and mips), `renderer` (the `Passes`),
//! `read_back`, `baked` (the `nostencil bake` entry), `targets`, `stats`, `techniques`.

pub mod atlas;
pub mod atlas_vertices;
pub mod bake;
pub mod bake_cache;
pub mod baked;
pub mod light;
pub mod maps;
pub mod page;
pub mod page_targets;
pub mod passes;
pub mod read_back;
pub mod rebake;
pub mod renderer;
pub mod stats;
pub mod targets;
pub mod techniques;
pub mod texel_surface;

#[cfg(test)]
pub use super::options::ShadowAtlasOptions;
pub use super::options::{AtlasBake, LightMode, ShadowKind};
#[cfg(test)]
pub use baked::Baked;
pub use baked::{bake, BakeStep};
#[cfg(test)]
pub use light::scene_bounds;
pub use light::ShadowLightUniforms;
pub use stats::ShadowAtlasStats;
pub use techniques::{PROJECTIVE_TEXTURE, SHADOW_MAP, SHADOW_TEXTURE_ATLAS};
