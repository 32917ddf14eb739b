//! The atlas page (`page`) on the GPU: one shadow texture with mips holding every model's tile,
//! the raw page the rasterised bake writes, the tiles' records and the texel surfaces of the
//! meshes whose atlas covers every texel (geometry images, a quad mapped whole), and the
//! recording of the page's passes:
//! - `atlas bake`: the other meshes (charts with gutters, skins), drawn at their atlas UVs into
//!   their tile of the raw page (one viewport per tile);
//! - `atlas page`: one quad per re-baked tile into mip 0 of the page, which bakes a texel
//!   tile's texels from their surface points and dilates a rasterised tile from the raw page
//!   (a pipeline each);
//! - `atlas mips`: one blit chain for the page.
//!
//! Mip 0 is loaded, not cleared: tiles that were not re-baked keep their texels.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec4};
use gpu_allocator::MemoryLocation;

use super::atlas::MeshAtlas;
use super::page::{pack, PageLayout, Tile};
use super::targets::{self, Framebuffer, ImageView, RenderPass};
use super::texel_surface::{packed, texel_surface};
use crate::error::{Error, Result};
use crate::frame::offscreen;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::{Buffer, Image};
use crate::gpu::texture::{self, Sampler};
use crate::gpu::Gpu;
use crate::render::per_slot::slot_copy;
use crate::render::Pipeline;
use crate::render::{FrameRecorder, GpuMesh, ObjectPush};
use crate::scene::Scene;
use crate::technique::options::AtlasBake;

/// One tile as the page pass reads it (`shaders/atlas_page_tiles.glsl`, std430).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct TileRecord {
    model: Mat4,
    /// x, y, side; where the texels' surface points start (one uvec4 each), -1 for a
    /// rasterised tile.
    rect: [i32; 4],
    /// x: the dilation radius.
    params: [i32; 4],
}

/// One tile as the scene pass samples it (`shaders/atlas_page_sample.glsl`, std140).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct TileUniform {
    rect: [f32; 4],
    mips: [f32; 4],
}

/// The page pass's two pipelines (same layout and vertex shader).
#[derive(Clone, Copy)]
pub struct PagePipelines<'p> {
    /// Texel tiles, baked from their texels' surface points.
    pub texels: &'p Pipeline,
    /// Rasterised tiles, dilated from the raw page.
    pub dilate: &'p Pipeline,
}

/// How a model's tile is baked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TileBake {
    /// A mesh whose atlas covers every texel centre (a geometry image, a quad mapped whole):
    /// one fragment per texel, from its surface point.
    Texels,
    /// Triangles at their atlas UVs into the raw page, then dilation.
    Rasterised,
}

/// One model's shadow texture in the page.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PageTile {
    pub tile: Tile,
    pub mip_levels: u32,
    pub bake: TileBake,
    dilate_radius: u32,
}

/// A texel no tile covers: lit, no coverage.
const LIT_UNCOVERED: [f32; 4] = [1.0, 1.0, 1.0, 0.0];

/// Every model's shadow texture as tiles of one page.
pub struct AtlasPage {
    pub layout: PageLayout,
    /// By object index.
    pub tiles: Vec<PageTile>,
    pub mip_levels: u32,
    /// Mip 0 of the raw page when some tile is rasterised, else 1 x 1 (bound, never read).
    raw_extent: vk::Extent2D,
    // Field order is drop order: sets and framebuffers before the buffers, views and images.
    /// Per object: the page and its tile, set 2 of the scene pass.
    pub scene_sets: Vec<DescriptorSet>,
    /// Per frame slot, the tiles' records and the set that binds them with the texel surfaces
    /// (set 1 of the page pass): a frame whose models moved writes its slot's copy.
    tile_slots: Vec<TileSlot>,
    /// The slot the last `write_models` wrote: the page pass of its frame reads it.
    slot: usize,
    /// The records as the CPU last wrote them (a new slot's copy starts from them).
    records: Vec<TileRecord>,
    /// The raw page, read texel by texel: set 2 of the page pass.
    pub raw_set: DescriptorSet,
    raw_framebuffer: Framebuffer,
    page_framebuffer: Framebuffer,
    _mip0: ImageView,
    /// Per mip count of some tile, a view of the page with that many levels (sampling through
    /// it keeps the LOD within the tile's clean mips).
    _level_views: Vec<(u32, ImageView)>,
    _uniforms: Buffer,
    surface: Buffer,
    pub raw: Image,
    pub texture: Image,
    pub raster_pass: RenderPass,
    pub page_pass: RenderPass,
    /// The page pass's first run: mip 0 cleared (lit, no coverage) over the whole page in the
    /// pass, where a tiler clears it in tile memory; later runs load it to re-bake some tiles.
    page_clear_pass: RenderPass,
    /// Mip 0 was written by a page pass already (later runs load it).
    page_written: std::sync::atomic::AtomicBool,
    _trilinear: Sampler,
    _nearest: Sampler,
}

impl AtlasPage {
    /// Lays every object's shadow texture out in one page (`layouts` by mesh index) and creates
    /// it, cleared to lit with no coverage. `bake`: whether meshes covering their tile are baked by their
    /// texels or rasterised like other meshes.
    pub fn new(gpu: &Arc<Gpu>, scene: &Scene, layouts: &[MeshAtlas], bake: AtlasBake) -> Result<Self> {
        if scene.objects.is_empty() {
            return Err(Error::InvalidInput(format!("scene '{}' has no objects", scene.name)));
        }
        let layout_of = |object: &crate::scene::SceneObject| {
            layouts.get(object.mesh).ok_or_else(|| {
                Error::Internal(format!("object '{}' has no atlas for mesh {}", object.name, object.mesh))
            })
        };
        let sides = scene.objects.iter().map(|o| layout_of(o).map(|l| l.size)).collect::<Result<Vec<_>>>()?;
        let max_side = gpu.device.info.limits.max_image_dimension2_d.min(crate::gpu::mobile_profile::MAX_IMAGE_SIDE);
        let layout = pack(&sides, max_side)?;

        let (surface, surface_start) = texel_surfaces(scene, layouts, bake);
        let tiles: Vec<PageTile> = scene
            .objects
            .iter()
            .zip(&layout.tiles)
            .map(|(object, &tile)| {
                let atlas = layout_of(object)?;
                let texels = object.skin.is_none() && surface_start[object.mesh].is_some();
                Ok(PageTile {
                    tile,
                    mip_levels: atlas.mip_levels,
                    bake: if texels { TileBake::Texels } else { TileBake::Rasterised },
                    dilate_radius: atlas.dilate_radius,
                })
            })
            .collect::<Result<_>>()?;
        let mip_levels = tiles.iter().map(|t| t.mip_levels).max().unwrap_or(1);
        let rasterised = tiles.iter().any(|t| t.bake == TileBake::Rasterised);

        let page_extent = vk::Extent2D { width: layout.width, height: layout.height };
        let raw_extent = if rasterised { page_extent } else { vk::Extent2D { width: 1, height: 1 } };
        let texture = targets::shadow_texture_page(gpu, "shadow-texture atlas page", page_extent, mip_levels)?;
        let raw = targets::shadow_texture_page(gpu, "shadow-texture atlas page (raw bake)", raw_extent, 1)?;
        // No clear here: the first page pass clears mip 0 in the pass (lit, no coverage, where no
        // tile covers a texel), the mips above are blitted from it where tiles lie (the rest of
        // the page is never sampled), and each raster pass clears the raw page where it bakes.
        texture::ready_for_sampling(gpu, &[(&texture, 0..0), (&raw, 0..0)], LIT_UNCOVERED)?;
        let mip0 = ImageView::mip(gpu, &texture, 0)?;
        let raster_pass = targets::colour_render_pass(gpu, true, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)?;
        let page_pass = offscreen::colour_render_pass_loaded(
            gpu,
            targets::SHADOW_TEXTURE_FORMAT,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        )?;
        let page_clear_pass = offscreen::colour_render_pass_loaded_first(
            gpu,
            targets::SHADOW_TEXTURE_FORMAT,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        )?;
        let raw_framebuffer = Framebuffer::new(gpu, &raster_pass, raw.view, raw_extent)?;
        let page_framebuffer = Framebuffer::new(gpu, &page_pass, mip0.raw, page_extent)?;

        let surface = surface_buffer(gpu, surface)?;
        let tile_slot = tile_slot(gpu, tiles.len(), &surface)?;
        let (uniforms, stride) = tile_uniforms(gpu, &layout, &tiles)?;
        let trilinear = Sampler::new(gpu, vk::Filter::LINEAR, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let nearest = Sampler::new(gpu, vk::Filter::NEAREST, vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let (scene_sets, level_views) = scene_sets(gpu, &texture, &tiles, (&uniforms, stride), &trilinear)?;
        let raw_set = DescriptorSet::new(gpu, &[texture_binding(raw.view, &nearest)])?;
        let mut page = AtlasPage {
            layout,
            tiles,
            mip_levels,
            raw_extent,
            scene_sets,
            tile_slots: vec![tile_slot],
            slot: 0,
            records: Vec::new(),
            raw_set,
            raw_framebuffer,
            page_framebuffer,
            _mip0: mip0,
            _level_views: level_views,
            _uniforms: uniforms,
            surface,
            raw,
            texture,
            raster_pass,
            page_pass,
            page_clear_pass,
            page_written: std::sync::atomic::AtomicBool::new(false),
            _trilinear: trilinear,
            _nearest: nearest,
        };
        page.write_records(scene, &surface_start, layouts)?;
        Ok(page)
    }

    /// Every tile's record: its model matrix (rewritten when models move: `write_models`), rect
    /// and where its texel surface starts.
    fn write_records(&mut self, scene: &Scene, surface_start: &[Option<usize>], layouts: &[MeshAtlas]) -> Result<()> {
        self.records = scene
            .objects
            .iter()
            .zip(&self.tiles)
            .map(|(object, t)| {
                let start = match t.bake {
                    TileBake::Texels => surface_start.get(object.mesh).copied().flatten().map_or(-1, |s| s as i32),
                    TileBake::Rasterised => -1,
                };
                let radius = layouts.get(object.mesh).map_or(0, |l| l.dilate_radius);
                TileRecord {
                    model: object.transform,
                    rect: [t.tile.x as i32, t.tile.y as i32, t.tile.size as i32, start],
                    params: [radius as i32, 0, 0, 0],
                }
            })
            .collect();
        let records = &self.records;
        self.tile_slots.iter_mut().try_for_each(|slot| slot.records.write(0, records))
    }

    /// The tiles' model matrices, as the scene now places its objects, into frame slot
    /// `slot`'s records (made on its first use), which this frame's page pass reads.
    pub fn write_models(&mut self, gpu: &Arc<Gpu>, scene: &Scene, slot: usize) -> Result<()> {
        for (record, object) in self.records.iter_mut().zip(&scene.objects) {
            record.model = object.transform;
        }
        let (count, surface) = (self.tiles.len(), &self.surface);
        let copy = slot_copy(&mut self.tile_slots, slot, || tile_slot(gpu, count, surface))?;
        copy.records.write(0, &self.records)?;
        self.slot = slot;
        Ok(())
    }

    /// The tiles and texel surfaces as the page pass of the frame last written reads them.
    pub fn tiles_set(&self) -> &DescriptorSet {
        // Never empty: made with slot 0's.
        &self.tile_slots.get(self.slot).unwrap_or(&self.tile_slots[0]).set
    }

    /// Whether any of `tiles` (object indices) is rasterised.
    pub fn any_rasterised(&self, tiles: &[usize]) -> bool {
        tiles.iter().any(|&i| self.tiles.get(i).is_some_and(|t| t.bake == TileBake::Rasterised))
    }

    /// The rasterised tiles among `tiles`: each model drawn at its atlas UVs into its tile of
    /// the raw page (cleared: no coverage), lit or shadowed per texel. `draws` holds each
    /// object's mesh and pipeline (the bake or its skinned twin, which share the layout `sets`
    /// are bound for: the frame's and the lights').
    pub fn record_raster_bake(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draws: &[(&GpuMesh, &Pipeline)],
        sets: &[vk::DescriptorSet],
        tiles: &[usize],
    ) {
        let clear = [vk::ClearValue { color: vk::ClearColorValue { float32: LIT_UNCOVERED } }];
        let rasterised: Vec<usize> = tiles
            .iter()
            .copied()
            .filter(|&i| self.tiles.get(i).is_some_and(|t| t.bake == TileBake::Rasterised))
            .collect();
        let area = self.area_of(&rasterised, self.raw_extent);
        rec.begin_offscreen_pass_in(&self.raster_pass, self.raw_framebuffer.raw, self.raw_extent, area, &clear);
        let mut bound = None;
        for &index in &rasterised {
            let (Some(t), Some(object), Some(&(mesh, bake))) =
                (self.tiles.get(index), scene.objects.get(index), draws.get(index))
            else {
                continue;
            };
            if !bound.is_some_and(|b| std::ptr::eq(b, bake)) {
                rec.bind_with_sets(bake, sets);
                bound = Some(bake);
            }
            rec.set_viewport_rect(vk::Rect2D {
                offset: vk::Offset2D { x: t.tile.x as i32, y: t.tile.y as i32 },
                extent: vk::Extent2D { width: t.tile.size, height: t.tile.size },
            });
            rec.push(bake, &ObjectPush { model: object.transform, colour: Vec4::ONE });
            rec.draw_mesh(mesh);
        }
        rec.end_render_pass();
    }

    /// `tiles` (object indices, ascending) written into mip 0 of the page: one quad each, a
    /// draw per run of consecutive tiles baked alike, `texels` for texel tiles and
    /// `dilate` for rasterised tiles (two pipelines, not a branch: a software rasteriser would
    /// run both sides for every texel).
    pub fn record_page(
        &self,
        rec: &mut FrameRecorder,
        pipelines: PagePipelines,
        light_set: vk::DescriptorSet,
        tiles: &[usize],
    ) {
        let extent = vk::Extent2D { width: self.layout.width, height: self.layout.height };
        if self.page_written.swap(true, std::sync::atomic::Ordering::Relaxed) {
            let area = self.area_of(tiles, extent);
            rec.begin_offscreen_pass_in(&self.page_pass, self.page_framebuffer.raw, extent, area, &[]);
        } else {
            let clear = [vk::ClearValue { color: vk::ClearColorValue { float32: LIT_UNCOVERED } }];
            let whole = vk::Rect2D { offset: vk::Offset2D::default(), extent };
            rec.begin_offscreen_pass_in(&self.page_clear_pass, self.page_framebuffer.raw, extent, whole, &clear);
        }
        let sets = [light_set, self.tiles_set().set, self.raw_set.set];
        let push = [extent.width as f32, extent.height as f32, 0.0, 0.0];
        let mut bound = None;
        for (bake, first, count) in self.runs(tiles) {
            let pipeline = match bake {
                TileBake::Texels => pipelines.texels,
                TileBake::Rasterised => pipelines.dilate,
            };
            if bound != Some(bake) {
                rec.bind_with_sets(pipeline, &sets);
                rec.push(pipeline, &push);
                bound = Some(bake);
            }
            rec.draw(6, count, 0, first as u32);
        }
        rec.end_render_pass();
    }

    /// `tiles` (ascending) as runs of consecutive tiles baked alike: (bake, first, count).
    fn runs(&self, tiles: &[usize]) -> Vec<(TileBake, usize, u32)> {
        let mut runs: Vec<(TileBake, usize, u32)> = Vec::new();
        for &index in tiles {
            let Some(tile) = self.tiles.get(index) else { continue };
            match runs.last_mut() {
                Some((bake, first, count)) if *bake == tile.bake && *first + *count as usize == index => *count += 1,
                _ => runs.push((tile.bake, index, 1)),
            }
        }
        runs
    }

    /// The render area of a pass over `tiles` (object indices): the smallest rectangle holding
    /// them, so that a re-bake of a few tiles loads and stores only theirs (`extent`: the
    /// whole page, when no tile is given).
    fn area_of(&self, tiles: &[usize], extent: vk::Extent2D) -> vk::Rect2D {
        let rects = tiles.iter().filter_map(|&i| self.tiles.get(i)).map(|t| t.tile);
        let (lo, hi) = rects.fold(((u32::MAX, u32::MAX), (0, 0)), |(lo, hi), t| {
            ((lo.0.min(t.x), lo.1.min(t.y)), (hi.0.max(t.x + t.size), hi.1.max(t.y + t.size)))
        });
        if lo.0 >= hi.0 || lo.1 >= hi.1 {
            return vk::Rect2D { offset: vk::Offset2D::default(), extent };
        }
        let (w, h) = ((hi.0 - lo.0).min(extent.width), (hi.1 - lo.1).min(extent.height));
        vk::Rect2D {
            offset: vk::Offset2D { x: lo.0 as i32, y: lo.1 as i32 },
            extent: vk::Extent2D { width: w, height: h },
        }
    }

    /// The page's mip chain from its mip 0, left ready for sampling.
    pub fn record_mips(&self, rec: &mut FrameRecorder) {
        rec.build_mips_from_sampled(self.texture.raw, self.layout.width, self.layout.height, self.mip_levels);
    }

    /// Bytes of GPU memory the page holds: its mips, the raw page, the tiles and texel
    /// surfaces.
    pub fn memory_bytes(&self) -> u64 {
        let texel = 4u64;
        let mips: u64 = (0..self.mip_levels)
            .map(|m| u64::from((self.layout.width >> m).max(1)) * u64::from((self.layout.height >> m).max(1)) * texel)
            .sum();
        let raw = u64::from(self.raw_extent.width) * u64::from(self.raw_extent.height) * texel;
        let records: u64 = self.tile_slots.iter().map(|slot| slot.records.size).sum();
        mips + raw + records + self.surface.size + self._uniforms.size
    }
}

/// The texel surfaces of the page, one block per mesh whose atlas covers every texel centre (a
/// geometry image, or a mesh mapped whole onto its square like the ground), shared by its
/// objects, and where each mesh's block starts. A skinned object is re-posed on the CPU each
/// frame, and a chart with a gutter needs dilating: both keep the rasterised bake.
fn texel_surfaces(scene: &Scene, layouts: &[MeshAtlas], bake: AtlasBake) -> (Vec<[u32; 4]>, Vec<Option<usize>>) {
    let mut surface: Vec<[u32; 4]> = Vec::new();
    let mut surface_start: Vec<Option<usize>> = vec![None; layouts.len()];
    for (mesh, atlas) in layouts.iter().enumerate() {
        let used_unskinned = scene.objects.iter().any(|o| o.mesh == mesh && o.skin.is_none());
        if !used_unskinned || bake == AtlasBake::Rasterised {
            continue;
        }
        if let Some(texels) = texel_surface(atlas) {
            surface_start[mesh] = Some(surface.len());
            surface.extend(texels.into_iter().map(packed));
        }
    }
    (surface, surface_start)
}

/// Each tile's rect on the page and mip figures for the scene pass, one uniform slice a tile
/// (slices `stride` bytes apart, the device's offset alignment).
fn tile_uniforms(gpu: &Arc<Gpu>, layout: &PageLayout, tiles: &[PageTile]) -> Result<(Buffer, u64)> {
    let alignment = gpu.device.info.limits.min_uniform_buffer_offset_alignment;
    let stride = aligned(std::mem::size_of::<TileUniform>() as u64, alignment);
    let mut uniforms = Buffer::new(
        gpu,
        "atlas page tiles (scene)",
        stride * tiles.len() as u64,
        vk::BufferUsageFlags::UNIFORM_BUFFER,
        MemoryLocation::CpuToGpu,
    )?;
    let (width, height) = (layout.width as f32, layout.height as f32);
    for (index, t) in tiles.iter().enumerate() {
        let uniform = TileUniform {
            rect: [
                t.tile.x as f32 / width,
                t.tile.y as f32 / height,
                t.tile.size as f32 / width,
                t.tile.size as f32 / height,
            ],
            mips: [(t.mip_levels - 1) as f32, t.tile.size as f32, 0.5 * (1u32 << (t.mip_levels - 1)) as f32, 0.0],
        };
        uniforms.write(index * stride as usize, std::slice::from_ref(&uniform))?;
    }
    Ok((uniforms, stride))
}

/// The texel surfaces the page pass reads (never empty: a storage buffer binding needs a
/// range).
fn surface_buffer(gpu: &Arc<Gpu>, mut surface: Vec<[u32; 4]>) -> Result<Buffer> {
    if surface.is_empty() {
        surface.push([0; 4]);
    }
    Buffer::device_local(gpu, "atlas page texel surfaces", &surface, vk::BufferUsageFlags::STORAGE_BUFFER)
}

/// One frame slot's tile records (`tile_count` of them, written by `write_records` and
/// `write_models`) and the set that binds them with the texel surfaces (the set first: it is
/// dropped before the buffer it names).
struct TileSlot {
    set: DescriptorSet,
    records: Buffer,
}

fn tile_slot(gpu: &Arc<Gpu>, tile_count: usize, surface: &Buffer) -> Result<TileSlot> {
    let records_size = (tile_count * std::mem::size_of::<TileRecord>()) as u64;
    let records = Buffer::new(
        gpu,
        "atlas page tiles",
        records_size,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::CpuToGpu,
    )?;
    let page_stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    let set = DescriptorSet::new(
        gpu,
        &[
            Binding::ReadOnlyStorage { buffer: records.raw, range: records_size, stages: page_stages },
            Binding::ReadOnlyStorage {
                buffer: surface.raw,
                range: surface.size,
                stages: vk::ShaderStageFlags::FRAGMENT,
            },
        ],
    )?;
    Ok(TileSlot { set, records })
}

/// A texture binding of the fragment stage, sampled with `sampler`.
fn texture_binding(view: vk::ImageView, sampler: &Sampler) -> Binding {
    Binding::Texture {
        view,
        sampler: sampler.raw,
        layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        stages: vk::ShaderStageFlags::FRAGMENT,
    }
}

/// Views of the page with a given number of mips, one per mip count the tiles have.
type LevelViews = Vec<(u32, ImageView)>;

/// The scene pass's set for each tile: the page through a view with as many mips as the tile
/// has (one view per mip count, returned to be kept alive) and the tile's uniform slice.
fn scene_sets(
    gpu: &Arc<Gpu>,
    texture: &Image,
    tiles: &[PageTile],
    (uniforms, stride): (&Buffer, u64),
    sampler: &Sampler,
) -> Result<(Vec<DescriptorSet>, LevelViews)> {
    let mut level_views: LevelViews = Vec::new();
    for t in tiles {
        if !level_views.iter().any(|(levels, _)| *levels == t.mip_levels) {
            level_views.push((t.mip_levels, ImageView::levels(gpu, texture, t.mip_levels)?));
        }
    }
    let view_of = |levels: u32| level_views.iter().find(|(l, _)| *l == levels).map_or(texture.view, |(_, v)| v.raw);
    let sets = tiles
        .iter()
        .enumerate()
        .map(|(index, t)| {
            DescriptorSet::new(
                gpu,
                &[
                    texture_binding(view_of(t.mip_levels), sampler),
                    Binding::UniformSlice {
                        buffer: uniforms.raw,
                        offset: index as u64 * stride,
                        range: std::mem::size_of::<TileUniform>() as u64,
                        stages: vk::ShaderStageFlags::FRAGMENT,
                    },
                ],
            )
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((sets, level_views))
}

fn aligned(size: u64, alignment: u64) -> u64 {
    let alignment = alignment.max(1);
    size.div_ceil(alignment) * alignment
}
