//! What the shadow-texture atlas sample (seed 004) needs from the engine and no port writes
//! twice: each mesh's atlas (its charts in a shadow texture, `mesh_atlas`), the tiles of one page
//! that hold every model's texture (`AtlasPage`: the page with its mips, the raw page the bake
//! writes, the tiles' records and the scene pass's per-tile sets), the light's view-projection
//! fitted to the scene, the shadow map image, and the pipeline layouts of the four passes. The
//! passes themselves (render passes, pipelines, draws) are the sample's.

use std::sync::Arc;

use ash::vk;

use super::{SampleBase, SampleBuffer, PUSH_BYTES};
use crate::error::{Error, Result, VkContext};
use crate::frame::offscreen::ImageView;
use crate::gpu::descriptors::DescriptorSet;
use crate::gpu::memory::{Buffer, Image};
use crate::gpu::texture::{record_mip_chain_from_sampled, Sampler};
use crate::gpu::Gpu;
use crate::render::object_push::draw_order;
use crate::technique::shadow_atlas::atlas::mesh_atlas;
use crate::technique::shadow_atlas::atlas_vertices::{atlas_vertices, surface_of};
use crate::technique::shadow_atlas::light::light_at;
use crate::technique::shadow_atlas::page_targets::AtlasPage;
use crate::technique::shadow_atlas::renderer::{light_uniforms, LightSlot};
use crate::technique::shadow_atlas::{maps, targets, AtlasBake, LightMode, ShadowKind, ShadowLightUniforms};

/// The shadow map's format (D16: depth attachment and sampling on every device).
pub const MAP_FORMAT: vk::Format = targets::SHADOW_MAP_FORMAT;
/// The shadow textures' format: R, G, B one light's visibility each, A coverage.
pub const PAGE_FORMAT: vk::Format = targets::SHADOW_TEXTURE_FORMAT;

/// The shadow atlas of the base's scene: what its four passes read and write (module docs).
pub struct ShadowAtlas {
    /// The scene light the shadow map is drawn from (its index: the map pass's push).
    pub map_light: u32,
    pub map_size: u32,
    /// The shadow map's one layer, for its framebuffer.
    pub map_view: vk::ImageView,
    /// The page, every model's shadow texture a tile of it (mip 0: the page pass's target).
    pub page_extent: vk::Extent2D,
    pub page_view: vk::ImageView,
    /// The raw page: the bake's target, read by the page pass.
    pub raw_view: vk::ImageView,
    /// Per object, its tile in the page (and in the raw page).
    pub tiles: Vec<vk::Rect2D>,
    /// Sets: frame 0, material 1, light 2 (`shadow_map.vert`).
    pub map_layout: vk::PipelineLayout,
    /// Sets: frame 0, light 1 (`shadow_atlas_bake.*`).
    pub bake_layout: vk::PipelineLayout,
    /// Sets: light 0, tiles 1, raw page 2 (`shadow_atlas_page_dilate.*`).
    pub page_layout: vk::PipelineLayout,
    /// Sets: frame 0, material 1, the object's tile 2, light 3 (`shadow_atlas_scene.*`).
    pub scene_layout: vk::PipelineLayout,
    _layouts: Layouts,
    frame_set: vk::DescriptorSet,
    /// Per object: its material's set and its mesh.
    materials: Vec<vk::DescriptorSet>,
    object_meshes: Vec<usize>,
    /// Per mesh: its atlas vertices, indices and index count.
    meshes: Vec<(SampleBuffer, SampleBuffer, u32)>,
    // Field order is drop order: sets and views before what they point at.
    light_set: DescriptorSet,
    _light_uniforms: Buffer,
    _page_mip0: ImageView,
    _map_layer: ImageView,
    page: AtlasPage,
    _compare: Sampler,
    _map: Image,
}

/// Pipeline layouts, destroyed on drop.
struct Layouts {
    gpu: Arc<Gpu>,
    raw: Vec<vk::PipelineLayout>,
}

impl Layouts {
    /// A layout of `sets` (set i: `sets[i]`) and the base's push constants.
    fn add(&mut self, sets: &[vk::DescriptorSetLayout]) -> Result<vk::PipelineLayout> {
        let push = [vk::PushConstantRange::default()
            .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT)
            .size(PUSH_BYTES)];
        let info = vk::PipelineLayoutCreateInfo::default().set_layouts(sets).push_constant_ranges(&push);
        // SAFETY: the device is alive; the set layouts are (their owners outlive the call).
        let layout = unsafe { self.gpu.raw().create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?;
        self.raw.push(layout);
        Ok(layout)
    }
}

impl Drop for Layouts {
    fn drop(&mut self) {
        for layout in self.raw.drain(..) {
            // SAFETY: the sample's submissions were waited for; each layout is destroyed once.
            unsafe { self.gpu.raw().destroy_pipeline_layout(layout, None) };
        }
    }
}

impl SampleBase {
    /// The scene's shadow atlas, as the engine lays it out for `--shadow-map-size map_size
    /// --shadow-texture-size texture_size --atlas-bake rasterised --light-motion fixed`.
    pub fn shadow_atlas(&self, map_size: u32, texture_size: u32) -> Result<ShadowAtlas> {
        let (gpu, scene) = (&self.gpu, &self.scene);
        let atlases = scene
            .meshes
            .iter()
            .map(|m| mesh_atlas(&m.name, &m.data, m.uv1.as_deref(), texture_size))
            .collect::<Result<Vec<_>>>()?;
        let mesh_buffers = scene
            .meshes
            .iter()
            .zip(&atlases)
            .map(|(m, a)| {
                let vertices = atlas_vertices(&a.positions, &a.normals, &a.uvs, &surface_of(m, &a.source_vertices));
                let count = a.indices.len() as u32;
                Ok((
                    self.vertex_buffer("atlas vertices", &vertices)?,
                    self.vertex_buffer("atlas indices", &a.indices)?,
                    count,
                ))
            })
            .collect::<Result<Vec<_>>>()?;
        let page = AtlasPage::new(gpu, scene, &atlases, AtlasBake::Rasterised)?;
        let coverage = maps::coverage(ShadowKind::Atlas, scene);
        let map_light = coverage
            .iter()
            .position(|c| c.layer() == Some(0))
            .ok_or_else(|| Error::InvalidInput(format!("scene '{}' has no light that casts shadows", scene.name)))?;
        let map = targets::shadow_map_image(gpu, map_size, maps::layer_count(&coverage))?;
        let map_layer = ImageView::layer(gpu, &map, 0, vk::ImageAspectFlags::DEPTH)?;
        let compare = Sampler::depth_compare(gpu)?;
        let light = light_at(scene, LightMode::Fixed, 0);
        let uniforms = ShadowLightUniforms::fitted(scene, &light, &coverage, map_size);
        let LightSlot { set: light_set, buffer: mut light_uniforms } = light_uniforms(gpu, &map, &compare)?;
        light_uniforms.write(0, std::slice::from_ref(&uniforms))?;
        let page_mip0 = ImageView::mip(gpu, &page.texture, 0)?;
        let tile_layout = page.scene_sets.first().ok_or_else(|| Error::Internal("an atlas of no tiles".into()))?.layout;
        let (frame, material, light_layout) = (self.frame.layout, self.gpu_scene.materials.layout(), light_set.layout);
        let mut layouts = Layouts { gpu: gpu.clone(), raw: Vec::new() };
        let map_layout = layouts.add(&[frame, material, light_layout])?;
        let bake_layout = layouts.add(&[frame, light_layout])?;
        let page_layout = layouts.add(&[light_layout, page.tiles_set().layout, page.raw_set.layout])?;
        let scene_layout = layouts.add(&[frame, material, tile_layout, light_layout])?;
        let tiles = page
            .tiles
            .iter()
            .map(|t| vk::Rect2D {
                offset: vk::Offset2D { x: t.tile.x as i32, y: t.tile.y as i32 },
                extent: vk::Extent2D { width: t.tile.size, height: t.tile.size },
            })
            .collect();
        Ok(ShadowAtlas {
            map_light: map_light as u32,
            map_size,
            map_view: map_layer.raw,
            page_extent: vk::Extent2D { width: page.layout.width, height: page.layout.height },
            page_view: page_mip0.raw,
            raw_view: page.raw.view,
            tiles,
            map_layout,
            bake_layout,
            page_layout,
            scene_layout,
            _layouts: layouts,
            frame_set: self.frame.set,
            materials: scene.objects.iter().map(|o| self.gpu_scene.materials.set(o.material)).collect(),
            object_meshes: scene.objects.iter().map(|o| o.mesh).collect(),
            meshes: mesh_buffers,
            light_set,
            _light_uniforms: light_uniforms,
            _page_mip0: page_mip0,
            _map_layer: map_layer,
            page,
            _compare: compare,
            _map: map,
        })
    }

    /// Viewport and scissor over `rect` (a target's, a tile's).
    pub fn viewport_rect(&self, cmd: vk::CommandBuffer, rect: vk::Rect2D) {
        let viewport = vk::Viewport {
            x: rect.offset.x as f32,
            y: rect.offset.y as f32,
            width: rect.extent.width as f32,
            height: rect.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: `cmd` is recording; every sample pipeline has a dynamic viewport and scissor.
        unsafe {
            self.device().cmd_set_viewport(cmd, 0, &[viewport]);
            self.device().cmd_set_scissor(cmd, 0, &[rect]);
        }
    }

    /// A framebuffer of `views` for `render_pass`, `extent` large, destroyed with the base.
    pub fn framebuffer_of(
        &self,
        render_pass: vk::RenderPass,
        views: &[vk::ImageView],
        extent: vk::Extent2D,
    ) -> Result<vk::Framebuffer> {
        let info = vk::FramebufferCreateInfo::default()
            .render_pass(render_pass)
            .attachments(views)
            .width(extent.width)
            .height(extent.height)
            .layers(1);
        // SAFETY: the device, the render pass and the views are alive.
        let framebuffer = unsafe { self.device().create_framebuffer(&info, None) }.vk("vkCreateFramebuffer")?;
        self.owned.borrow_mut().push(super::Owned::Framebuffer(framebuffer));
        Ok(framebuffer)
    }
}

impl ShadowAtlas {
    fn bind(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        layout: vk::PipelineLayout,
        first: u32,
        sets: &[vk::DescriptorSet],
    ) {
        // SAFETY: `cmd` is recording; the sets and the layout live as long as `self`.
        unsafe { device.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, layout, first, sets, &[]) };
    }

    /// The shadow map pass's sets: the frame's (0) and the light's (2).
    pub fn bind_map_sets(&self, base: &SampleBase, cmd: vk::CommandBuffer) {
        self.bind(base.device(), cmd, self.map_layout, 0, &[self.frame_set]);
        self.bind(base.device(), cmd, self.map_layout, 2, &[self.light_set.set]);
    }

    /// The bake's sets: the frame's (0) and the light's with the shadow map (1).
    pub fn bind_bake_sets(&self, base: &SampleBase, cmd: vk::CommandBuffer) {
        self.bind(base.device(), cmd, self.bake_layout, 0, &[self.frame_set, self.light_set.set]);
    }

    /// The page pass's sets: the light's (0), the tiles' records (1), the raw page (2).
    pub fn bind_page_sets(&self, base: &SampleBase, cmd: vk::CommandBuffer) {
        let sets = [self.light_set.set, self.page.tiles_set().set, self.page.raw_set.set];
        self.bind(base.device(), cmd, self.page_layout, 0, &sets);
    }

    /// The scene pass's shared sets: the frame's (0) and the light's (3).
    pub fn bind_scene_sets(&self, base: &SampleBase, cmd: vk::CommandBuffer) {
        self.bind(base.device(), cmd, self.scene_layout, 0, &[self.frame_set]);
        self.bind(base.device(), cmd, self.scene_layout, 3, &[self.light_set.set]);
    }

    /// Object `object`'s sets in the scene pass: its material (1) and its tile of the page (2).
    pub fn bind_object_sets(&self, base: &SampleBase, cmd: vk::CommandBuffer, object: usize) {
        if let (Some(&material), Some(tile)) = (self.materials.get(object), self.page.scene_sets.get(object)) {
            self.bind(base.device(), cmd, self.scene_layout, 1, &[material, tile.set]);
        }
    }

    /// Draws object `object`'s mesh (its atlas vertices) with the bound pipeline.
    pub fn draw_mesh(&self, base: &SampleBase, cmd: vk::CommandBuffer, object: usize) {
        let Some((vertices, indices, count)) = self.object_meshes.get(object).and_then(|&m| self.meshes.get(m)) else {
            return;
        };
        // SAFETY: `cmd` is recording in a pass with an atlas-vertex pipeline bound; the buffers
        // live as long as `self`.
        unsafe {
            let device = base.device();
            device.cmd_bind_vertex_buffers(cmd, 0, &[vertices.raw()], &[0]);
            device.cmd_bind_index_buffer(cmd, indices.raw(), 0, vk::IndexType::UINT32);
            device.cmd_draw_indexed(cmd, *count, 1, 0, 0, 0);
        }
    }

    /// The page's mips 1.. blitted from mip 0 (left for sampling by the page pass, its writes
    /// made visible to transfers), every mip then left for sampling.
    pub fn record_mips(&self, base: &SampleBase, cmd: vk::CommandBuffer) {
        let (width, height) = (self.page_extent.width, self.page_extent.height);
        record_mip_chain_from_sampled(&base.gpu, cmd, self.page.texture.raw, width, height, self.page.mip_levels);
    }

    /// The objects in the engine's draw order (opaque in scene order, then blended back to front).
    pub fn draw_order(&self, base: &SampleBase) -> Vec<usize> {
        draw_order(&base.scene).collect()
    }
}
