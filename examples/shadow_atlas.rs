//! Shadow textures baked into an atlas page (seed 004, Ryu and Oh's "A shadow texture to
//! represent the shadow including a non-convex object"), in one file read top to bottom: the
//! render passes, their pipelines with each blend state, and the draws in order.
//!
//!     cargo run --example shadow_atlas -- [--out FILE.png] [--stencil]
//!
//! No pass of this technique needs a stencil: the engine has no separate reference path for it
//! (`nostencil passes --technique shadow-texture-atlas` lists no stencil state), and `--stencil`
//! only gives the frame's depth attachment its stencil aspect, as `nostencil render --stencil
//! reference` does. `cargo test` proves both images equal, and equal to the engine's
//! (`nostencil render --technique shadow-texture-atlas --scene box --samples 1 --atlas-bake
//! rasterised`).
//!
//! The frame (docs/design/shadow-atlas.md):
//! 1. the shadow map: the casters from the light, depth only;
//! 2. the bake: each model drawn at its atlas UVs (`uv * 2 - 1` as its position) into its tile
//!    of the raw page, each texel lit (1) or shadowed (0) by the shadow map's depth compare at
//!    the surface point it holds; alpha 1 marks texels a triangle covered;
//! 3. the page: each tile's texels copied from the raw page, those no triangle covered taking
//!    their nearest covered neighbours' mean (dilation: filtering never reads the empty gutter);
//! 4. the page's mips, by blits;
//! 5. the scene: Lambert + ambient, the light's term times the model's shadow texture, sampled
//!    trilinearly at the vertex's atlas UV like any other texture.
//!
//! Steps 1-4 depend only on the light and the models: the engine skips them while neither
//! moves. What else it adds (geometry images baked per texel, several lights in R, G and B,
//! re-baking only the tiles a moved model can shadow) is in docs/shadow-textures.md.

use std::process::ExitCode;

use ash::vk;
use glam::{Mat4, Vec4};
use image::RgbaImage;
use nostencil::sample::{replace, PipelineParts, SampleBase, VertexInput};
use nostencil::Gpu;

/// The scene `main` draws: one box over the ground under a directional light.
pub const SCENE: &str = "box";
pub const WIDTH: u32 = 160;
pub const HEIGHT: u32 = 120;
/// The shadow map's side in texels (the engine's `--shadow-map-size`).
pub const MAP_SIZE: u32 = 512;
/// A shadow texture's side for meshes that are not geometry images (`--shadow-texture-size`).
pub const TEXTURE_SIZE: u32 = 256;
/// What the bake and the page start from: lit, no coverage.
const LIT_UNCOVERED: [f32; 4] = [1.0, 1.0, 1.0, 0.0];

/// The object push (`shaders/object_push.glsl`): 80 bytes.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ObjectPush {
    model: Mat4,
    /// rgb: the material's base colour factor; a: the alpha the draw writes.
    colour: Vec4,
}

/// The shadow map pass's push (`shaders/light_push.glsl`): the object's, and which light.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct LightPush {
    object: ObjectPush,
    light: [u32; 4],
}

fn main() -> ExitCode {
    nostencil::sample::run("shadow_atlas", |gpu, stencil| render(gpu, SCENE, stencil))
}

/// The frame of built-in scene `scene` with its shadow textures; with a stencil aspect in the
/// depth attachment when `stencil` (unused: the technique needs none).
pub fn render(gpu: &std::sync::Arc<Gpu>, scene: &str, stencil: bool) -> nostencil::Result<RgbaImage> {
    let base = SampleBase::new(gpu, scene, WIDTH, HEIGHT, stencil)?;
    let device = base.device();
    // The engine's atlas of each mesh (charts packed in a square, a power of two a side), the
    // tiles of one page holding every model's, the light's view fitted around the scene.
    let atlas = base.shadow_atlas(MAP_SIZE, TEXTURE_SIZE)?;

    // --- The render passes. Each offscreen one clears its target and leaves it for the next
    // pass's fragment shader (or the mips' blits) to read.
    let map_pass = offscreen_pass(&base, nostencil::sample::MAP_FORMAT, true)?;
    let bake_pass = offscreen_pass(&base, nostencil::sample::PAGE_FORMAT, false)?;
    let page_pass = offscreen_pass(&base, nostencil::sample::PAGE_FORMAT, false)?;
    let frame_pass = frame_pass(&base)?;
    let map_extent = vk::Extent2D { width: atlas.map_size, height: atlas.map_size };
    let map_framebuffer = base.framebuffer_of(map_pass, &[atlas.map_view], map_extent)?;
    let bake_framebuffer = base.framebuffer_of(bake_pass, &[atlas.raw_view], atlas.page_extent)?;
    let page_framebuffer = base.framebuffer_of(page_pass, &[atlas.page_view], atlas.page_extent)?;
    let framebuffer = base.create_framebuffer(frame_pass)?;

    // --- The pipelines. None blends: every pass replaces what it writes.
    use vk::{CompareOp as Cmp, CullModeFlags as Cull};
    let rgba = vk::ColorComponentFlags::RGBA;
    // 1. The shadow map: depth LESS and written, no colour, both faces.
    let shadow_map = base.pipeline_in(
        atlas.map_layout,
        &PipelineParts {
            render_pass: map_pass,
            vertex_shader: "shadow_map.vert",
            fragment_shader: "shadow_map.frag",
            vertex_input: VertexInput::Atlas,
            cull: Cull::NONE,
            depth_test: Some(Cmp::LESS),
            depth_write: true,
            blend: replace(vk::ColorComponentFlags::empty()),
            stencil: None,
        },
    )?;
    // 2. The bake: RGBA replaced (blend off), no depth, no culling (atlas space has no facing).
    let bake = base.pipeline_in(
        atlas.bake_layout,
        &PipelineParts {
            render_pass: bake_pass,
            vertex_shader: "shadow_atlas_bake.vert",
            fragment_shader: "shadow_atlas_bake.frag",
            vertex_input: VertexInput::Atlas,
            blend: replace(rgba),
            ..PipelineParts::default()
        },
    )?;
    // 3. The page: one quad per tile (from the vertex and instance index), RGBA replaced (blend
    // off), each texel dilated from the raw page within its tile.
    let page = base.pipeline_in(
        atlas.page_layout,
        &PipelineParts {
            render_pass: page_pass,
            vertex_shader: "shadow_atlas_page_dilate.vert",
            fragment_shader: "shadow_atlas_page_dilate.frag",
            blend: replace(rgba),
            ..PipelineParts::default()
        },
    )?;
    // 5. The scene: Lambert + ambient, the light's term times the shadow texture; RGBA replaced
    // (blend off), depth LESS and written, back faces culled.
    let lit = base.pipeline_in(
        atlas.scene_layout,
        &PipelineParts {
            render_pass: frame_pass,
            vertex_shader: "shadow_atlas_scene.vert",
            fragment_shader: "shadow_atlas_scene.frag",
            vertex_input: VertexInput::Atlas,
            cull: Cull::BACK,
            depth_test: Some(Cmp::LESS),
            depth_write: true,
            blend: replace(rgba),
            stencil: None,
        },
    )?;

    let bind = |cmd: vk::CommandBuffer, pipeline: vk::Pipeline| {
        // SAFETY: `cmd` is recording in a pass.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline) };
    };
    let begin = |cmd: vk::CommandBuffer, pass, framebuffer, extent: vk::Extent2D, clear: &[vk::ClearValue]| {
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent };
        let info = vk::RenderPassBeginInfo::default()
            .render_pass(pass)
            .framebuffer(framebuffer)
            .render_area(area)
            .clear_values(clear);
        // SAFETY: `cmd` is recording outside a pass; the pass and framebuffer are the base's.
        unsafe { device.cmd_begin_render_pass(cmd, &info, vk::SubpassContents::INLINE) };
        base.viewport_rect(cmd, area);
    };
    let end = |cmd: vk::CommandBuffer| {
        // SAFETY: a pass was begun on `cmd`.
        unsafe { device.cmd_end_render_pass(cmd) };
    };
    let far = vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } };
    let lit_uncovered = vk::ClearValue { color: vk::ClearColorValue { float32: LIT_UNCOVERED } };
    let objects = &base.scene.objects;

    // --- The draws, in order.
    base.render(|cmd| {
        // 1. The shadow map: every caster from the light.
        begin(cmd, map_pass, map_framebuffer, map_extent, &[far]);
        bind(cmd, shadow_map);
        atlas.bind_map_sets(&base, cmd);
        for (index, object) in objects.iter().enumerate().filter(|(_, o)| o.casts_shadow) {
            let object_push = ObjectPush { model: object.transform, colour: Vec4::ONE };
            base.push(cmd, bytemuck::bytes_of(&LightPush { object: object_push, light: [atlas.map_light, 0, 0, 0] }));
            atlas.draw_mesh(&base, cmd, index);
        }
        end(cmd);
        // 2. The bake: each model at its atlas UVs, its tile of the raw page the viewport.
        begin(cmd, bake_pass, bake_framebuffer, atlas.page_extent, &[lit_uncovered]);
        bind(cmd, bake);
        atlas.bind_bake_sets(&base, cmd);
        for (index, object) in objects.iter().enumerate() {
            base.viewport_rect(cmd, atlas.tiles[index]);
            base.push(cmd, bytemuck::bytes_of(&ObjectPush { model: object.transform, colour: Vec4::ONE }));
            atlas.draw_mesh(&base, cmd, index);
        }
        end(cmd);
        // 3. The page: one quad per tile (instance i: object i's tile), dilated.
        begin(cmd, page_pass, page_framebuffer, atlas.page_extent, &[lit_uncovered]);
        bind(cmd, page);
        atlas.bind_page_sets(&base, cmd);
        let page_size = [atlas.page_extent.width as f32, atlas.page_extent.height as f32, 0.0, 0.0];
        base.push(cmd, bytemuck::bytes_of(&page_size));
        // SAFETY: `cmd` is recording in the page pass with its pipeline and sets bound.
        unsafe { device.cmd_draw(cmd, 6, objects.len() as u32, 0, 0) };
        end(cmd);
        // 4. The page's mips.
        atlas.record_mips(&base, cmd);
        // 5. The scene, each object reading its tile of the page.
        let background = base.scene.background;
        let clear = [vk::ClearValue { color: vk::ClearColorValue { float32: background.extend(0.0).to_array() } }, far];
        begin(cmd, frame_pass, framebuffer, base.extent, &clear);
        bind(cmd, lit);
        atlas.bind_scene_sets(&base, cmd);
        for index in atlas.draw_order(&base) {
            let object = &objects[index];
            atlas.bind_object_sets(&base, cmd, index);
            let colour = base.scene.base_colour(object).extend(1.0);
            base.push(cmd, bytemuck::bytes_of(&ObjectPush { model: object.transform, colour }));
            atlas.draw_mesh(&base, cmd, index);
        }
        end(cmd);
        Ok(())
    })
}

/// A one-attachment render pass (the shadow map's depth, or a shadow texture's colour):
/// cleared, stored, and left for sampling; it waits for the reads and blits before it and makes
/// its writes visible to those after it.
fn offscreen_pass(base: &SampleBase, format: vk::Format, depth: bool) -> nostencil::Result<vk::RenderPass> {
    let (layout, final_layout, stages, write) = if depth {
        (
            vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::DEPTH_STENCIL_READ_ONLY_OPTIMAL,
            vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS,
            vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ,
        )
    } else {
        (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
        )
    };
    let attachment = [vk::AttachmentDescription::default()
        .format(format)
        .samples(vk::SampleCountFlags::TYPE_1)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
        .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(final_layout)];
    let reference = [vk::AttachmentReference { attachment: 0, layout }];
    let subpass = vk::SubpassDescription::default().pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS);
    let subpass =
        [if depth { subpass.depth_stencil_attachment(&reference[0]) } else { subpass.color_attachments(&reference) }];
    let outside = vk::PipelineStageFlags::FRAGMENT_SHADER | vk::PipelineStageFlags::TRANSFER;
    let reads = vk::AccessFlags::SHADER_READ | vk::AccessFlags::TRANSFER_READ;
    let dependencies = [
        vk::SubpassDependency::default()
            .src_subpass(vk::SUBPASS_EXTERNAL)
            .dst_subpass(0)
            .src_stage_mask(outside)
            .src_access_mask(reads)
            .dst_stage_mask(stages)
            .dst_access_mask(write),
        vk::SubpassDependency::default()
            .src_subpass(0)
            .dst_subpass(vk::SUBPASS_EXTERNAL)
            .src_stage_mask(stages)
            .src_access_mask(write)
            .dst_stage_mask(outside)
            .dst_access_mask(reads),
    ];
    base.create_render_pass(
        &vk::RenderPassCreateInfo::default().attachments(&attachment).subpasses(&subpass).dependencies(&dependencies),
    )
}

/// The frame's render pass: colour (copied out after it) and depth (with the reference's unused
/// stencil), one subpass.
fn frame_pass(base: &SampleBase) -> nostencil::Result<vk::RenderPass> {
    let colour = vk::AttachmentDescription::default()
        .format(nostencil::sample::COLOUR_FORMAT)
        .samples(vk::SampleCountFlags::TYPE_1)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
    let depth = vk::AttachmentDescription::default()
        .format(base.depth_format)
        .samples(vk::SampleCountFlags::TYPE_1)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::DONT_CARE)
        .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
        .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    let colour_ref = [vk::AttachmentReference { attachment: 0, layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL }];
    let depth_ref =
        vk::AttachmentReference { attachment: 1, layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL };
    let subpass = [vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&colour_ref)
        .depth_stencil_attachment(&depth_ref)];
    let to_copy = [vk::SubpassDependency::default()
        .src_subpass(0)
        .dst_subpass(vk::SUBPASS_EXTERNAL)
        .src_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)
        .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags::TRANSFER)
        .dst_access_mask(vk::AccessFlags::TRANSFER_READ)];
    let attachments = [colour, depth];
    base.create_render_pass(
        &vk::RenderPassCreateInfo::default().attachments(&attachments).subpasses(&subpass).dependencies(&to_copy),
    )
}
