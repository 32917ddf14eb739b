//! What a seed 004 frame reports besides its image: whether the cached shadow map and bake
//! were skipped, and how each mesh was laid out in its atlas.

use std::any::Any;

use super::atlas::AtlasSource;
use crate::technique::interface::FrameStats;
use crate::technique::options::{LightMode, ShadowKind};

/// One mesh laid out in its atlas.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AtlasInfo {
    pub mesh: String,
    pub source: AtlasSource,
    pub size: u32,
    pub mip_levels: u32,
    /// Why the file's TEXCOORD_1 was not used (overlapping), when it has one.
    pub rejected_uv1: Option<String>,
}

impl AtlasInfo {
    pub fn describe(&self) -> String {
        match &self.rejected_uv1 {
            None => self.source.describe(),
            Some(why) => format!("{} (TEXCOORD_1 rejected: {why})", self.source.describe()),
        }
    }
}

/// What a frame did besides its image.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ShadowAtlasStats {
    pub technique: ShadowKind,
    pub light: LightMode,
    /// Frames rendered by this renderer, this one included.
    pub frame: u32,
    /// The shadow map (and bake) were skipped: neither light nor models moved.
    pub cached: bool,
    pub map_size: u32,
    pub atlases: Vec<AtlasInfo>,
}

impl FrameStats for ShadowAtlasStats {
    fn report(&self) -> String {
        let mut out = format!(
            "{} | light {} | frame {}: {} | shadow map {}x{}",
            self.technique.name(),
            self.light.name(),
            self.frame,
            if self.cached {
                "shadow map and bake skipped (neither light nor models moved since the last frame)"
            } else {
                "shadow map re-rendered (and shadow textures re-baked)"
            },
            self.map_size,
            self.map_size
        );
        if self.technique == ShadowKind::Atlas {
            for atlas in &self.atlases {
                out.push_str(&format!(
                    "\n  atlas of '{}': {} -> {}x{} shadow texture, {} mips",
                    atlas.mesh,
                    atlas.describe(),
                    atlas.size,
                    atlas.size,
                    atlas.mip_levels
                ));
            }
        }
        out
    }

    fn json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or_default()
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
