//! The selection outline without a stencil (seed 003), in one file read top to bottom: the
//! frame's render pass, its pipelines with each blend state's formula, and its draws in order.
//!
//!     cargo run --example outline -- [--out FILE.png] [--stencil]
//!
//! `--stencil` draws the same frame with a real stencil, as the document does; `cargo test`
//! proves both images equal, and equal to the engine's (`nostencil render --technique outline
//! --scene outline --select box --samples 1`).
//!
//! The frame (docs/outline.md, docs/design/outlines.md):
//! 1. the objects that are not selected, writing alpha 0 (the clear's alpha is 0 too);
//! 2. the selected objects, writing alpha 1: their mark, where the document writes stencil 1.
//!    Drawn after the others, so the mark means "the visible surface here is selected";
//! 3. each selected object's copy, pushed out along its smooth normals by the outline's width
//!    in pixels, depth test off, in the outline colour where alpha is 0 and nowhere else: the
//!    blend keeps the pixel where alpha is 1, exactly where a stencil test `NOT_EQUAL 1` fails.
//!
//! What the engine adds on top (the document's scaled copy, a blurred outline) is in
//! docs/porting.md.

use std::process::ExitCode;

use ash::vk;
use glam::{Mat4, Vec4};
use image::RgbaImage;
use nostencil::sample::{blend, replace, stencil_face, PipelineParts, SampleBase, VertexInput};
use nostencil::Gpu;

/// The scene `main` draws: a box and a sphere that intersect, a torus knot behind them and a
/// torus in front of the box, over the ground.
pub const SCENE: &str = "outline";
/// The objects outlined, by name (the engine's default: the scene's first shadow caster).
pub const SELECTED: &[&str] = &["box"];
pub const WIDTH: u32 = 160;
pub const HEIGHT: u32 = 120;
/// The outline's width in pixels (the engine's `--outline-width`).
pub const OUTLINE_WIDTH: f32 = 4.0;
/// The outline's colour as the PNG shows it, sRGB (the engine's `--outline-colour #FFA000`).
pub const OUTLINE_COLOUR: [u8; 3] = [0xFF, 0xA0, 0x00];
/// The reference's mark: stencil 1 under the selected objects' visible surface.
const STENCIL_SELECTED: u32 = 1;

/// The cartoon shaders' push constants (`shaders/cartoon_push.glsl`): 112 bytes. The first 80
/// are laid out as `object_push.glsl`'s.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CartoonPush {
    model: Mat4,
    /// rgb: the object's colour or the outline's; a: the alpha the draw writes.
    colour: Vec4,
    /// `cartoon_shade`: x toon ramp, y rim ramp, z ink only (all 0: Lambert).
    /// `cartoon_extrude`: x the extrusion in pixels.
    params: Vec4,
    /// The frame in pixels (xy) and the world size of one pixel at unit distance from the eye.
    viewport: Vec4,
}

fn main() -> ExitCode {
    nostencil::sample::run("outline", |gpu, stencil| render(gpu, SCENE, stencil))
}

/// The frame of built-in scene `scene` with the objects named in [`SELECTED`] outlined, marked
/// in alpha, or in a real stencil when `stencil`.
pub fn render(gpu: &std::sync::Arc<Gpu>, scene: &str, stencil: bool) -> nostencil::Result<RgbaImage> {
    let base = SampleBase::new(gpu, scene, WIDTH, HEIGHT, stencil)?;
    let device = base.device();
    let selected = base.selection(SELECTED)?;
    // Set 2 of the scene pass: the toon and rim ramps `cartoon_shade.frag` declares (unread
    // when it shades Lambert).
    let ramps = base.cartoon_ramps()?;

    // --- The render pass: one subpass, colour (alpha kept) and depth (stencil: reference only).
    let colour = vk::AttachmentDescription::default()
        .format(nostencil::sample::COLOUR_FORMAT)
        .samples(vk::SampleCountFlags::TYPE_1)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
    // Depth and stencil live and die in the pass (on a tiler they never leave tile memory).
    let depth = vk::AttachmentDescription::default()
        .format(base.depth_format)
        .samples(vk::SampleCountFlags::TYPE_1)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::DONT_CARE)
        .stencil_load_op(if stencil { vk::AttachmentLoadOp::CLEAR } else { vk::AttachmentLoadOp::DONT_CARE })
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
    // The frame's colour is copied out after the pass.
    let to_copy = [vk::SubpassDependency::default()
        .src_subpass(0)
        .dst_subpass(vk::SUBPASS_EXTERNAL)
        .src_stage_mask(vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT)
        .src_access_mask(vk::AccessFlags::COLOR_ATTACHMENT_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags::TRANSFER)
        .dst_access_mask(vk::AccessFlags::TRANSFER_READ)];
    let attachments = [colour, depth];
    let pass = base.create_render_pass(
        &vk::RenderPassCreateInfo::default().attachments(&attachments).subpasses(&subpass).dependencies(&to_copy),
    )?;
    let framebuffer = base.create_framebuffer(pass)?;

    // --- The pipelines.
    let (rgba, rgb) = (
        vk::ColorComponentFlags::RGBA,
        vk::ColorComponentFlags::R | vk::ColorComponentFlags::G | vk::ColorComponentFlags::B,
    );
    use vk::{BlendFactor as F, BlendOp as Op, CompareOp as Cmp, CullModeFlags as Cull};
    // The scene: Lambert over the material (`cartoon_shade`), RGBA replaced, alpha = the push's
    // (0 unselected, 1 selected), depth LESS and written, back faces culled.
    let scene_parts = PipelineParts {
        render_pass: pass,
        vertex_shader: "cartoon_shade.vert",
        fragment_shader: "cartoon_shade.frag",
        vertex_input: VertexInput::Scene,
        cull: Cull::BACK,
        depth_test: Some(Cmp::LESS),
        depth_write: true,
        blend: replace(rgba),
        stencil: None,
    };
    let shade = base.pipeline_in(ramps.layout, &scene_parts)?;
    // The reference's selected objects: the same, also writing stencil 1 (ALWAYS, REPLACE).
    let mark = stencil_face(Cmp::ALWAYS, STENCIL_SELECTED, vk::StencilOp::REPLACE);
    let stencil_shade =
        base.pipeline_in(ramps.layout, &PipelineParts { stencil: Some((mark, mark)), ..scene_parts })?;
    // The copies (`cartoon_extrude.vert`; `cartoon_colour.frag` writes the push's colour): no
    // depth test (the outline shows through what stands in front), no culling, colour only.
    let copy = PipelineParts {
        render_pass: pass,
        vertex_shader: "cartoon_extrude.vert",
        fragment_shader: "cartoon_colour.frag",
        vertex_input: VertexInput::PositionNormal,
        ..PipelineParts::default()
    };
    // Where alpha is 0: dst.rgb = src.rgb * (1 - dst.a) + dst.rgb * dst.a (ADD,
    // ONE_MINUS_DST_ALPHA, DST_ALPHA): the outline where unmarked (0), the pixel kept where
    // marked (1). Alpha is written by no one (RGB only): the mark stays for every copy.
    let outline = base.pipeline(&PipelineParts {
        blend: blend(Op::ADD, F::ONE_MINUS_DST_ALPHA, F::DST_ALPHA, rgb)
            .src_alpha_blend_factor(F::ONE)
            .dst_alpha_blend_factor(F::ZERO),
        ..copy
    })?;
    // The reference: the copy replaces RGB where the stencil is NOT_EQUAL 1 (and writes none).
    let mut unmarked = stencil_face(Cmp::NOT_EQUAL, STENCIL_SELECTED, vk::StencilOp::KEEP);
    unmarked.write_mask = 0;
    let stencil_outline =
        base.pipeline(&PipelineParts { blend: replace(rgb), stencil: Some((unmarked, unmarked)), ..copy })?;

    // Each selected object's copy: its mesh welded by position (no seam cracks it open when
    // pushed out), one smooth normal per vertex.
    let copies = (0..base.scene.objects.len())
        .filter(|&index| selected[index])
        .map(|index| {
            let copy = base.smooth_copy(index)?;
            let vertices = base.vertex_buffer("copy vertices", &copy.vertices)?;
            Ok((index, vertices, base.vertex_buffer("copy indices", &copy.indices)?, copy.indices.len() as u32))
        })
        .collect::<nostencil::Result<Vec<_>>>()?;
    // What turns pixels into a distance: one pixel at unit distance from the eye spans
    // 2 tan(fov / 2) / height; the vertex shader scales it by the vertex's distance.
    let pixel = 2.0 * (0.5 * base.scene.camera.fov_y_radians).tan() / HEIGHT as f32;
    let viewport = Vec4::new(WIDTH as f32, HEIGHT as f32, pixel, 0.0);
    let outline_colour = nostencil::sample::linear_colour(OUTLINE_COLOUR);
    let bind = |cmd: vk::CommandBuffer, pipeline: vk::Pipeline| {
        // SAFETY: `cmd` is recording in the pass.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline) };
    };

    // --- The draws, in order.
    base.render(|cmd| {
        let background = base.scene.background;
        let clear = [
            // Alpha 0 where nothing is drawn: unmarked.
            vk::ClearValue { color: vk::ClearColorValue { float32: background.extend(0.0).to_array() } },
            vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } },
        ];
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(pass)
            .framebuffer(framebuffer)
            .render_area(vk::Rect2D { offset: vk::Offset2D::default(), extent: base.extent })
            .clear_values(&clear);
        // SAFETY: `cmd` is recording; the pass and framebuffer are the base's.
        unsafe { device.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE) };
        base.whole_frame(cmd);
        // 1. The objects not selected, alpha 0. Lambert: params 0, pushed once whole; each
        //    object then pushes its transform and colour over the first 80 bytes. Set 0 first
        //    (with the base's layout), then set 2: binding set 0 again with a layout that agrees
        //    on it leaves set 2 bound.
        bind(cmd, shade);
        base.bind_frame_uniforms(cmd);
        ramps.bind(cmd);
        let lambert = CartoonPush { model: Mat4::IDENTITY, colour: Vec4::ONE, params: Vec4::ZERO, viewport };
        base.push(cmd, bytemuck::bytes_of(&lambert));
        base.draw_objects_with(cmd, |i, object| (!selected[i]).then(|| base.object_push(object, 0.0)));
        // 2. The selected objects, alpha 1 (the reference: stencil 1 as well).
        if stencil {
            bind(cmd, stencil_shade);
        }
        base.draw_objects_with(cmd, |i, object| selected[i].then(|| base.object_push(object, 1.0)));
        // 3. The copies, in the outline colour where unmarked.
        bind(cmd, if stencil { stencil_outline } else { outline });
        for (index, vertices, indices, count) in &copies {
            let push = CartoonPush {
                model: base.scene.objects[*index].transform,
                colour: outline_colour,
                params: Vec4::new(OUTLINE_WIDTH, 0.0, 0.0, 0.0),
                viewport,
            };
            base.push(cmd, bytemuck::bytes_of(&push));
            // SAFETY: `cmd` is recording in the pass with an outline pipeline bound; the buffers
            // live until `render` returns.
            unsafe {
                device.cmd_bind_vertex_buffers(cmd, 0, &[vertices.raw()], &[0]);
                device.cmd_bind_index_buffer(cmd, indices.raw(), 0, vk::IndexType::UINT32);
                device.cmd_draw_indexed(cmd, *count, 1, 0, 0, 0);
            }
        }
        // SAFETY: the pass was begun above.
        unsafe { device.cmd_end_render_pass(cmd) };
        Ok(())
    })
}
