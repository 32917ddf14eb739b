//! The seed 004 renderer's part (`Passes`): the shadow maps (a layer per shadowing light), the
//! lights' uniforms, the atlas vertices and (atlas only) every model's shadow texture, built
//! once; per frame, where the lights are, whether one of them or a model moved (else the shadow
//! maps and bake are skipped: cached), and the draws of each pass.

use std::sync::Arc;

use ash::vk;
use glam::Vec4;
use gpu_allocator::MemoryLocation;

use super::atlas::{light_view_layout, mesh_atlas, MeshAtlas};
use super::atlas_vertices::{upload_bind_poses, PosedLayout};
use super::bake::AtlasTargets;
use super::bake_cache::{stale_tiles, CacheKey, Shadowing};
use super::light::{light_at, ShadowLightUniforms};
use super::maps::{self, Coverage};
use super::page_targets::{AtlasPage, PagePipelines};
use super::passes::{
    self, AtlasDraw, AtlasKinds, AtlasSet, AtlasTarget, LIGHT_OR_CASTERS_MOVED, RASTERISED_TILES_STALE,
};
use super::read_back::ShadowTextures;
use super::rebake::Sphere;
use super::stats::{AtlasInfo, PageStats, ShadowAtlasStats};
use super::targets::{self, Framebuffer, ImageView, RenderPass};
use crate::error::{Error, Result};
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::{Buffer, Image};
use crate::gpu::texture::Sampler;
use crate::gpu::Gpu;
use crate::render::gpu_mesh::object_draw;
use crate::render::object_push::draw_order;
use crate::render::passes::Passes;
use crate::render::per_slot::slot_copy;
use crate::render::plan::{MaterialVariant, PlannedPass, When};
use crate::render::Pipeline;
use crate::render::{
    object_push, FrameOutput, FrameRecorder, GpuMaterials, GpuMesh, LightPush, ObjectPush, Renderer, Skinning,
};
use crate::scene::{JointPalettes, Light, Scene, SlotPoses};
use crate::technique::frame_renderer::{self, FrameRenderer};
use crate::technique::interface::{FrameStats, RenderOptions};
use crate::technique::options::{LightMode, ShadowAtlasOptions, ShadowKind};

/// Everything a seed 004 frame needs, built once for a scene.
pub struct ShadowPasses {
    gpu: Arc<Gpu>,
    kind: ShadowKind,
    options: ShadowAtlasOptions,
    /// The projective texture's per-model textures.
    atlas: Option<AtlasTargets>,
    /// The shadow-texture atlas: every model's texture a tile of one page.
    page: Option<AtlasPage>,
    /// Each mesh's bounding sphere (which tiles a moved model can shadow).
    bounds: Vec<Sphere>,
    /// Per scene light: its map layer, or why it has none.
    coverage: Vec<Coverage>,
    // Field order is drop order: the sets and framebuffers before the views and map they
    // point at.
    /// Per frame slot, the lights' uniforms and the set that binds them with the map: a frame
    /// writes its slot's while the one before may still read its own.
    lights: Vec<LightSlot>,
    /// One per layer of the map array.
    map_framebuffers: Vec<Framebuffer>,
    _map_layers: Vec<ImageView>,
    map_pass: RenderPass,
    compare: Sampler,
    map: Image,
    meshes: Vec<GpuMesh>,
    /// Per object, skinned on the GPU: its bind pose's atlas vertices with joints and weights
    /// (`VertexLayout::SKINNED_ATLAS`), drawn by the pipelines' skinned twins.
    skinned: Vec<Option<GpuMesh>>,
    /// Where the skinned objects' palettes lie, skinning on the GPU.
    palettes: Option<JointPalettes>,
    materials: GpuMaterials,
    layouts: Vec<PosedLayout>,
    /// The pose each slot's copy of the skinned objects' atlas vertices holds.
    posed: SlotPoses,
    /// The frame slot `prepare` wrote last: the copies this frame's draws read.
    slot: usize,
    atlases: Vec<AtlasInfo>,
    /// Frames rendered, the current one not included until its statistics are taken.
    frames: u32,
    /// Frames prepared: which one this is (the moving light's clock; with frames in flight
    /// their statistics come later).
    prepared: u32,
    cache: Option<CacheKey>,
    /// This frame's light, whether the cached passes run, and the objects whose
    /// shadow textures they re-bake (ascending).
    light: Light,
    fresh: bool,
    rebake: Vec<usize>,
}

/// Builds the `kind` renderer for `scene`, calling `progress(done, total)` as each mesh's atlas
/// is laid out (generating atlases for many or large meshes takes a while).
pub fn build<'s>(
    technique: &'static str,
    kind: ShadowKind,
    gpu: &Arc<Gpu>,
    scene: &'s Scene,
    options: &RenderOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<FrameRenderer<'s, AtlasKinds, ShadowPasses>> {
    // Checked before the atlases are laid out, which takes a while.
    options.check()?;
    let atlas_options = options.shadow_atlas;
    let lights = maps::planned_lights(&maps::coverage(kind, scene), scene);
    frame_renderer::build_typed(technique, passes::plan(kind, &lights), gpu, scene, options, |_| {
        ShadowPasses::new(gpu, scene, kind, (atlas_options, options.skinning), progress)
    })
}

/// Each mesh's layout in its shadow texture, `progress` told after each: an atlas, or for the
/// projective texture (which needs none, nor the time or the failures of one) the light's view.
fn mesh_layouts(
    scene: &Scene,
    kind: ShadowKind,
    options: ShadowAtlasOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<MeshAtlas>> {
    let total = scene.meshes.len();
    scene
        .meshes
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let atlas = match kind {
                ShadowKind::Projective => Ok(light_view_layout(&m.data, options.map_size)),
                _ => mesh_atlas(&m.name, &m.data, m.uv1.as_deref(), options.texture_size),
            };
            progress(i + 1, total);
            atlas
        })
        .collect()
}

/// One frame slot's light uniforms (the set first: it is dropped before the buffer it names).
pub(crate) struct LightSlot {
    pub(crate) set: DescriptorSet,
    pub(crate) buffer: Buffer,
}

/// The shadow light's uniform buffer, and the set that binds it with the shadow `map` read
/// through the depth-compare sampler `compare`.
pub(crate) fn light_uniforms(gpu: &Arc<Gpu>, map: &Image, compare: &Sampler) -> Result<LightSlot> {
    let light_size = std::mem::size_of::<ShadowLightUniforms>() as u64;
    let light_buffer =
        Buffer::new(gpu, "shadow light", light_size, vk::BufferUsageFlags::UNIFORM_BUFFER, MemoryLocation::CpuToGpu)?;
    let light_set = DescriptorSet::new(
        gpu,
        &[
            Binding::UniformBuffer {
                buffer: light_buffer.raw,
                range: light_size,
                stages: vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
            },
            Binding::Texture {
                view: map.view,
                sampler: compare.raw,
                layout: vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
                stages: vk::ShaderStageFlags::FRAGMENT,
            },
        ],
    )?;
    Ok(LightSlot { set: light_set, buffer: light_buffer })
}

impl ShadowPasses {
    /// `skinning`: where skinned objects are posed (the atlas's texel tiles are of rigid
    /// objects only: a skinned object's tile is rasterised, by a pass with a skinned twin).
    pub(super) fn new(
        gpu: &Arc<Gpu>,
        scene: &Scene,
        kind: ShadowKind,
        (options, skinning): (ShadowAtlasOptions, Skinning),
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self> {
        let layouts = mesh_layouts(scene, kind, options, progress)?;
        let posed_layouts: Vec<PosedLayout> =
            scene.meshes.iter().zip(&layouts).map(|(m, a)| PosedLayout::of(m, a)).collect();
        let meshes = scene
            .meshes
            .iter()
            .zip(&layouts)
            .zip(&posed_layouts)
            .map(|((m, a), posed)| {
                let interleaved = posed.laid_out(a);
                GpuMesh::from_raw(gpu, &m.name, &interleaved, &a.indices)
            })
            .collect::<Result<Vec<_>>>()?;
        let materials = GpuMaterials::upload(gpu, scene)?;
        let palettes = (skinning == Skinning::Gpu).then(|| JointPalettes::of(scene));
        let skinned = match &palettes {
            Some(palettes) => upload_bind_poses(gpu, scene, &posed_layouts, palettes)?,
            None => Vec::new(),
        };
        let atlases = scene
            .meshes
            .iter()
            .zip(&layouts)
            .map(|(m, a)| AtlasInfo {
                mesh: m.name.clone(),
                source: a.source,
                size: a.size,
                mip_levels: a.mip_levels,
                rejected_uv1: a.rejected_uv1.clone(),
            })
            .collect();

        let coverage = maps::coverage(kind, scene);
        let layers = maps::layer_count(&coverage);
        let map = targets::shadow_map_image(gpu, options.map_size, layers)?;
        let map_pass = targets::shadow_map_render_pass(gpu)?;
        let map_extent = vk::Extent2D { width: options.map_size, height: options.map_size };
        // Without a light that has one, layer 0 is still bound, so still cleared (`passes::plan`).
        let map_layers = (0..layers.max(1))
            .map(|layer| ImageView::layer(gpu, &map, layer, vk::ImageAspectFlags::DEPTH))
            .collect::<Result<Vec<_>>>()?;
        let map_framebuffers = map_layers
            .iter()
            .map(|view| Framebuffer::new(gpu, &map_pass, view.raw, map_extent))
            .collect::<Result<Vec<_>>>()?;
        let compare = Sampler::depth_compare(gpu)?;
        let lights = vec![light_uniforms(gpu, &map, &compare)?];
        let atlas = match kind {
            ShadowKind::Projective => Some(AtlasTargets::new(gpu, scene, &layouts)?),
            ShadowKind::Map | ShadowKind::Atlas => None,
        };
        let page = match kind {
            ShadowKind::Atlas => Some(AtlasPage::new(gpu, scene, &layouts, options.bake)?),
            ShadowKind::Map | ShadowKind::Projective => None,
        };
        let bounds = scene.meshes.iter().map(|m| Sphere::around(&m.data.positions)).collect();
        Ok(ShadowPasses {
            gpu: gpu.clone(),
            kind,
            options,
            atlas,
            page,
            bounds,
            coverage,
            lights,
            map_framebuffers,
            _map_layers: map_layers,
            map_pass,
            compare,
            map,
            meshes,
            skinned,
            palettes,
            materials,
            layouts: posed_layouts,
            posed: SlotPoses::new(scene),
            slot: 0,
            atlases,
            frames: 0,
            prepared: 0,
            cache: None,
            light: scene.light(),
            fresh: true,
            rebake: Vec::new(),
        })
    }

    pub fn atlases(&self) -> &[AtlasInfo] {
        &self.atlases
    }

    /// The shadow textures to read back: the atlas page's tiles or the projective textures.
    pub fn shadow_textures(&self) -> Option<ShadowTextures<'_>> {
        match (&self.page, &self.atlas) {
            (Some(page), _) => Some(ShadowTextures::Page(page)),
            (None, Some(atlas)) => Some(ShadowTextures::PerModel(atlas)),
            (None, None) => None,
        }
    }

    /// Frames rendered so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    pub fn gpu(&self) -> &Arc<Gpu> {
        &self.gpu
    }

    /// Skinned objects whose palette changed (`Scene::pose_at`) since slot `slot`'s copy was
    /// posed get their atlas vertices re-posed on the CPU and uploaded into it (the atlas
    /// layout stays).
    fn follow_pose(&mut self, scene: &Scene, slot: usize) -> Result<()> {
        if self.palettes.is_some() {
            // Every skinned object is skinned in the vertex stage: no copy to pose.
            return Ok(());
        }
        for index in self.posed.changed(scene, slot) {
            let object = &scene.objects[index];
            let (Some(skin), Some(mesh), Some(layout)) =
                (&object.skin, self.meshes.get_mut(object.mesh), self.layouts.get(object.mesh))
            else {
                continue;
            };
            let interleaved = layout.posed(skin);
            mesh.write_posed(&self.gpu, slot, &format!("{} atlas vertices (posed)", object.name), &interleaved)?;
        }
        Ok(())
    }

    fn atlas_targets(&self, pass: &PlannedPass<AtlasKinds>) -> Result<&AtlasTargets> {
        self.atlas.as_ref().ok_or_else(|| Error::Internal(format!("pass '{}' without shadow textures", pass.name)))
    }

    fn atlas_page(&self, pass: &PlannedPass<AtlasKinds>) -> Result<&AtlasPage> {
        self.page.as_ref().ok_or_else(|| Error::Internal(format!("pass '{}' without an atlas page", pass.name)))
    }

    /// The casters from the pass's light, depth only, into its layer; MASK casters through the
    /// pass's alpha-mask variant, with their material.
    fn draw_shadow_map(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        pass: &PlannedPass<AtlasKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        let Some(&opaque) = pipelines.first() else { return Ok(()) };
        let light = pass.light.unwrap_or(0);
        let framebuffer = self
            .coverage
            .get(usize::from(light))
            .and_then(|c| c.layer())
            .and_then(|layer| self.map_framebuffers.get(layer as usize))
            .ok_or_else(|| Error::Internal(format!("pass '{}': light {light} has no map layer", pass.name)))?;
        self.begin_map_layer(rec, framebuffer);
        let sets = [rec.frame_set(), self.materials.template_set(), self.light_slot().set.set];
        rec.bind_with_sets(opaque, &sets);
        let mut bound = opaque;
        for (index, object) in scene.objects.iter().enumerate().filter(|(_, o)| o.casts_shadow) {
            let variant = MaterialVariant::for_caster(scene.material_of(object));
            let (mesh, pipeline) =
                object_draw(scene, index, self.object_meshes(), pass.variant(pipelines, opaque, variant))?;
            if !std::ptr::eq(pipeline, bound) {
                // Every pipeline of the pass shares its set layouts: the material and the
                // lights stay bound.
                rec.bind(pipeline);
                bound = pipeline;
            }
            if variant.is_some() {
                rec.bind_material(pipeline, self.materials.set(object.material));
            }
            let push = ObjectPush { model: object.transform, colour: Vec4::ONE };
            rec.push(pipeline, &LightPush { object: push, light: [u32::from(light), 0, 0, 0] });
            rec.draw_mesh(mesh);
        }
        rec.end_render_pass();
        Ok(())
    }

    /// The map pass into `framebuffer` (a layer), cleared to the far plane.
    fn begin_map_layer(&self, rec: &mut FrameRecorder, framebuffer: &Framebuffer) {
        let clear = [vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } }];
        let extent = vk::Extent2D { width: self.options.map_size, height: self.options.map_size };
        rec.begin_offscreen_pass(&self.map_pass, framebuffer.raw, extent, &clear);
    }

    /// Layer 0 cleared and left for sampling, when no light has a map (`passes::plan`).
    fn clear_map(&self, rec: &mut FrameRecorder) -> Result<()> {
        let framebuffer =
            self.map_framebuffers.first().ok_or_else(|| Error::Internal("a map array without layers".into()))?;
        self.begin_map_layer(rec, framebuffer);
        rec.end_render_pass();
        Ok(())
    }

    /// Every object lit, each light's term scaled by its shadow texture or map compare (the
    /// recorder bound the pipeline with the frame's set and the first object's shadow set).
    fn draw_scene(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        pass: &PlannedPass<AtlasKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        let Some(&main) = pipelines.first() else { return Ok(()) };
        let mut bound = main;
        for index in draw_order(scene) {
            let object = &scene.objects[index];
            let variant = MaterialVariant::for_surface(scene.material_of(object));
            let (mesh, pipeline) =
                object_draw(scene, index, self.object_meshes(), pass.variant(pipelines, main, variant))?;
            if !std::ptr::eq(pipeline, bound) {
                rec.bind(pipeline);
                bound = pipeline;
            }
            if let Some(set) = self.shadow_texture_set(index) {
                rec.bind_sets(pipeline, 2, &[set]);
            }
            rec.bind_material(pipeline, self.materials.set(object.material));
            rec.push(pipeline, &object_push(scene, object, 1.0));
            rec.draw_mesh(mesh);
        }
        Ok(())
    }

    /// The meshes objects are drawn from (`gpu_mesh::object_draw`): the atlas vertices per
    /// mesh, and per object skinned on the GPU its bind pose.
    fn object_meshes(&self) -> (&[GpuMesh], &[Option<GpuMesh>]) {
        (&self.meshes, &self.skinned)
    }
}

impl ShadowPasses {
    /// Object `index`'s shadow texture as the scene pass binds it (set 2).
    fn shadow_texture_set(&self, index: usize) -> Option<vk::DescriptorSet> {
        match (&self.page, &self.atlas) {
            (Some(page), _) => page.scene_sets.get(index).map(|s| s.set),
            (None, Some(atlas)) => atlas.objects.get(index).map(|o| o.scene_set.set),
            (None, None) => None,
        }
    }

    /// The light uniforms of the frame slot `prepare` wrote last (slot 0's before any).
    fn light_slot(&self) -> &LightSlot {
        // Never empty: made with slot 0's.
        self.lights.get(self.slot).unwrap_or(&self.lights[0])
    }

    /// The sets of the seed 004 roles: the first object's where there is one per object.
    fn own_set(&self, set: AtlasSet) -> Option<&DescriptorSet> {
        let first = || self.atlas.as_ref().and_then(|a| a.objects.first());
        match (set, &self.page) {
            (AtlasSet::Light, _) => Some(&self.light_slot().set),
            (AtlasSet::ShadowTexture, Some(page)) => page.scene_sets.first(),
            (AtlasSet::ShadowTexture, None) => first().map(|o| &o.scene_set),
            (AtlasSet::RawBake, Some(page)) => Some(&page.raw_set),
            (AtlasSet::RawBake, None) => first().map(|o| &o.dilate_set),
            (AtlasSet::PageTiles, Some(page)) => Some(page.tiles_set()),
            (AtlasSet::PageTiles, None) => None,
        }
    }
}

impl Passes<AtlasKinds> for ShadowPasses {
    fn set(&self, set: AtlasSet) -> Option<&DescriptorSet> {
        self.own_set(set)
    }

    fn materials(&self) -> Option<&GpuMaterials> {
        Some(&self.materials)
    }

    fn draw(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        draw: AtlasDraw,
        pass: &PlannedPass<AtlasKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        let pipeline = || {
            pipelines.first().copied().ok_or_else(|| Error::Internal(format!("pass '{}' has no pipeline", pass.name)))
        };
        match draw {
            AtlasDraw::ShadowMap => self.draw_shadow_map(rec, scene, pass, pipelines)?,
            AtlasDraw::ClearMap => self.clear_map(rec)?,
            AtlasDraw::Bake => {
                let bake = pipeline()?;
                let draws = (0..scene.objects.len())
                    .map(|i| object_draw(scene, i, self.object_meshes(), bake))
                    .collect::<Result<Vec<_>>>()?;
                let sets = [rec.frame_set(), self.light_slot().set.set];
                self.atlas_page(pass)?.record_raster_bake(rec, scene, &draws, &sets, &self.rebake)
            }
            AtlasDraw::ProjectiveBake => {
                let targets = self.atlas_targets(pass)?;
                let bake = pipeline()?;
                let draws = targets
                    .objects
                    .iter()
                    .map(|o| object_draw(scene, o.object, self.object_meshes(), bake))
                    .collect::<Result<Vec<_>>>()?;
                let sets = [rec.frame_set(), self.light_slot().set.set];
                targets.record_bake(rec, scene, &draws, &sets);
            }
            AtlasDraw::Page => {
                let dilate = pipelines
                    .get(1)
                    .copied()
                    .ok_or_else(|| Error::Internal(format!("pass '{}' has no dilation pipeline", pass.name)))?;
                let pipelines = PagePipelines { texels: pipeline()?, dilate };
                self.atlas_page(pass)?.record_page(rec, pipelines, self.light_slot().set.set, &self.rebake)
            }
            AtlasDraw::Dilate => self.atlas_targets(pass)?.record_dilate(rec, pipeline()?),
            AtlasDraw::Mips => match &self.page {
                Some(page) => page.record_mips(rec),
                None => self.atlas_targets(pass)?.record_mips(rec),
            },
            AtlasDraw::Scene => self.draw_scene(rec, scene, pass, pipelines)?,
        }
        Ok(())
    }

    fn offscreen_pass(&self, target: AtlasTarget) -> Option<(vk::RenderPass, usize)> {
        match (target, &self.page, &self.atlas) {
            (AtlasTarget::ShadowMap, _, _) => Some((self.map_pass.raw, 0)),
            (AtlasTarget::AtlasSpace, Some(page), _) => Some((page.raster_pass.raw, 1)),
            (AtlasTarget::PageMip0, Some(page), _) => Some((page.page_pass.raw, 1)),
            (AtlasTarget::LightSpace, _, Some(atlas)) => Some((atlas.bake_pass.raw, 1)),
            (AtlasTarget::TextureMip0, _, Some(atlas)) => Some((atlas.dilate_pass.raw, 1)),
            _ => None,
        }
    }

    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()> {
        let slot = renderer.slot();
        self.follow_pose(scene, slot)?;
        self.light = light_at(scene, self.options.light, self.prepared);
        self.prepared += 1;
        let primary = scene.primary_light_index();
        let geometries: Vec<Light> = scene
            .lights
            .iter()
            .enumerate()
            .map(|(i, l)| if Some(i) == primary { self.light } else { l.geometry() })
            .collect();
        let mut key = CacheKey::of(scene, &geometries);
        // Nothing moved: the fit (which walks every posed vertex) is the cached one.
        let unmoved = self.cache.as_ref().filter(|c| key.unmoved_since(c));
        self.rebake.clear();
        match unmoved {
            Some(cache) => {
                key.fitted = cache.fitted.clone();
                self.fresh = false;
            }
            None => {
                let uniforms = ShadowLightUniforms::fitted(scene, &self.light, &self.coverage, self.options.map_size);
                key.fitted = bytemuck::bytes_of(&uniforms).to_vec();
                self.fresh = true;
                if self.page.is_some() {
                    let shadowing =
                        Shadowing { bounds: &self.bounds, coverage: &self.coverage, map_size: self.options.map_size };
                    self.rebake = stale_tiles(scene, self.cache.as_ref(), &key, &geometries, shadowing);
                }
                if let Some(page) = &mut self.page {
                    page.write_models(&self.gpu, scene, slot)?;
                }
            }
        }
        // The slot's uniforms are the map's, whichever frame fitted them (a slot's copy may
        // be from before the last fit).
        let (gpu, map, compare) = (&self.gpu, &self.map, &self.compare);
        let light = slot_copy(&mut self.lights, slot, || light_uniforms(gpu, map, compare))?;
        light.buffer.write(0, &key.fitted)?;
        self.slot = slot;
        // The next frame's cache is what this one leaves in the map and textures.
        self.cache = Some(key);
        Ok(())
    }

    fn frame_light(&self) -> Option<Light> {
        Some(self.light)
    }

    fn conditions(&self, _scene: &Scene) -> Vec<When> {
        let mut conditions = Vec::new();
        if self.fresh {
            conditions.push(When::If(LIGHT_OR_CASTERS_MOVED));
        }
        if self.page.as_ref().is_some_and(|page| page.any_rasterised(&self.rebake)) {
            conditions.push(When::If(RASTERISED_TILES_STALE));
        }
        conditions
    }

    fn stats(&mut self, _output: &FrameOutput, _scene: &Scene) -> Box<dyn FrameStats> {
        self.frames += 1;
        Box::new(ShadowAtlasStats {
            technique: self.kind,
            light: self.options.light,
            frame: self.frames,
            cached: !self.fresh,
            map_size: self.options.map_size,
            atlases: self.atlases.clone(),
            page: self.page.as_ref().map(|page| PageStats::of(page, &self.coverage, self.options.map_size)),
            rebaked_tiles: self.rebake.len(),
        })
    }

    /// Every kind keeps several frames in flight: the light uniforms, posed vertices and the
    /// atlas page's tile records are per slot, and the map, the per-model textures and the page
    /// are written and read in queue order (each render pass and mip chain waits for the reads
    /// before it).
    fn writes_per_slot(&self) -> bool {
        true
    }

    fn joint_palettes(&self) -> Option<&JointPalettes> {
        self.palettes.as_ref()
    }

    fn frames_to_steady_state(&self) -> u32 {
        match self.options.light {
            LightMode::Moving => 1,
            LightMode::Fixed => 2,
        }
    }
}
