//! Shadow textures baked into a per-model atlas (seed 004, docs/design/shadow-atlas.md), and the plain
//! shadow map they are compared with.
//!
//! Pre-pass (outside the frame's render pass, skipped when neither lights nor models moved):
//! 1. shadow maps: per shadowing light, casters from it, depth only, into its layer of one
//!    depth array stored for sampling (`maps` decides which lights get one);
//! 2. (atlas) bake: per model, its triangles drawn at their atlas UV (`uv * 2 - 1`), each texel
//!    compared against every light's map (hardware compare, slope-scaled bias), light i's
//!    visibility in channel i (R, G, B: up to 3 lights);
//! 3. (atlas) dilate: texels no triangle covered take their nearest chart's value;
//! 4. (atlas) mips: built with blits.
//!
//! Frame: the scene lit with Lambert + ambient, each light's Lambert term scaled by its
//! channel of the model's shadow texture (sampled trilinearly) or by its map's compare.
//!
//! Files: `passes` (pipelines and the plan), `maps` (which lights get a map layer and a baked
//! channel), `light` (fitting each light's view), `bake` (the
//! per-model bake, dilation and mips), `renderer` (the `Passes`), `read_back`, `baked` (the
//! `nostencil bake` entry), `atlas` (layouts), `targets`, `stats`, `techniques`.

pub mod atlas;
pub mod bake;
pub mod baked;
pub mod light;
pub mod maps;
pub mod passes;
pub mod read_back;
pub mod renderer;
pub mod stats;
pub mod targets;
pub mod techniques;

pub use super::options::{check_size, LightMode, ShadowAtlasOptions, ShadowKind};
pub use baked::{bake, BakeStep, Baked};
pub use light::{light_at, light_view_projection, scene_bounds, ShadowLightUniforms, MOVING_LIGHT_STEP};
pub use stats::{AtlasInfo, ShadowAtlasStats};
pub use techniques::{technique_of, ShadowTechnique, PROJECTIVE_TEXTURE, SHADOW_MAP, SHADOW_TEXTURE_ATLAS};
