//! What a seed 004 frame reports besides its image: whether the cached shadow map and bake
//! were skipped, and how each mesh was laid out in its atlas.

use std::any::Any;

use super::atlas::AtlasSource;
use super::maps::Coverage;
use super::page_targets::{AtlasPage, TileBake};
use super::targets::SHADOW_MAP_FORMAT;
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
    /// The atlas page (the shadow-texture atlas only).
    pub page: Option<PageStats>,
    /// Models whose shadow textures this frame re-baked (0 when cached).
    pub rebaked_tiles: usize,
}

/// The atlas page, and what it costs a port: its memory, and the bytes a tile-based GPU moves
/// to and from memory for the shadow passes of a frame.
#[derive(Debug, Clone, serde::Serialize)]
pub struct PageStats {
    pub width: u32,
    pub height: u32,
    pub mip_levels: u32,
    pub tiles: usize,
    /// Tiles baked by their texels (geometry images); the rest are rasterised and dilated.
    pub texel_tiles: usize,
    /// The page with its mips, the raw page, the tiles' records and the texel surfaces.
    pub memory_bytes: u64,
    /// A frame that re-bakes every tile: the maps stored, the raw page stored (when a tile is
    /// rasterised), mip 0 of the page loaded and stored, each mip read and the next written.
    pub tiler_bytes_moving: u64,
    /// A frame where nothing moved: every shadow pass is skipped.
    pub tiler_bytes_fixed: u64,
}

impl PageStats {
    pub(crate) fn of(page: &AtlasPage, coverage: &[Coverage], map_size: u32) -> PageStats {
        let texel = 4u64; // RGBA8
        let (width, height) = (u64::from(page.layout.width), u64::from(page.layout.height));
        let maps = coverage.iter().filter(|c| c.layer().is_some()).count() as u64;
        let map_bytes = maps * u64::from(map_size) * u64::from(map_size) * map_texel_bytes();
        let rasterised = page.tiles.iter().any(|t| t.bake == TileBake::Rasterised);
        let raw_bytes = if rasterised { width * height * texel } else { 0 };
        let level = |m: u32| (width >> m).max(1) * (height >> m).max(1) * texel;
        let mips: u64 = (1..page.mip_levels).map(|m| level(m - 1) + level(m)).sum();
        PageStats {
            width: page.layout.width,
            height: page.layout.height,
            mip_levels: page.mip_levels,
            tiles: page.tiles.len(),
            texel_tiles: page.tiles.iter().filter(|t| t.bake == TileBake::Texels).count(),
            memory_bytes: page.memory_bytes(),
            tiler_bytes_moving: map_bytes + raw_bytes + 2 * level(0) + mips,
            tiler_bytes_fixed: 0,
        }
    }
}

fn map_texel_bytes() -> u64 {
    match SHADOW_MAP_FORMAT {
        ash::vk::Format::D16_UNORM => 2,
        _ => 4,
    }
}

fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1024.0 * 1024.0)
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
        if let Some(page) = &self.page {
            out.push_str(&format!(
                "\n  atlas page {}x{}, {} mips, {} tiles ({} baked by their texels, {} rasterised): {:.2} MiB; \
                 re-baked {} of {} tiles this frame",
                page.width,
                page.height,
                page.mip_levels,
                page.tiles,
                page.texel_tiles,
                page.tiles - page.texel_tiles,
                mib(page.memory_bytes),
                self.rebaked_tiles,
                page.tiles
            ));
            out.push_str(&format!(
                "\n  a tiler moves {:.2} MiB a frame for the shadow maps and page when everything is re-baked, {:.2} MiB \
                 when nothing moved",
                mib(page.tiler_bytes_moving),
                mib(page.tiler_bytes_fixed)
            ));
        }
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
