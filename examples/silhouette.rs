//! Ink silhouettes by the inverted hull (seed 002, Marshall's "Cartoon Rendering: Real-time
//! Silhouette Edge Detection and Rendering", its two-pass method), in one file read top to
//! bottom: the frame's render pass, its pipelines with each blend state's formula, and its draws
//! in order.
//!
//!     cargo run --example silhouette -- [--out FILE.png] [--stencil]
//!
//! No pass of this technique needs a stencil, in the engine's reference path or its emulated
//! one: `--stencil` gives the depth attachment its stencil aspect (as `nostencil render
//! --stencil reference` does) and changes nothing else; `cargo test` proves both images equal,
//! and equal to the engine's (`nostencil render --technique silhouette --silhouette hull
//! --scene duck --samples 1`).
//!
//! The frame:
//! 1. the scene, shaded Lambert (`cartoon_shade`), depth written;
//! 2. each object's copy pushed out along its smooth normals by the line width in pixels, its
//!    front faces culled: only its back faces draw, and they pass the depth test only where
//!    they stick out beyond the object (its silhouette) or fold behind it. That rim is the ink.
//!
//! What the engine adds on top (edges found on the CPU and drawn as screen-space quads, the N.V
//! rim, the alpha test, per-class ink) is in docs/ink-and-toon.md.

use std::process::ExitCode;

use ash::vk;
use glam::{Mat4, Vec4};
use image::RgbaImage;
use nostencil::sample::{replace, PipelineParts, SampleBase, VertexInput};
use nostencil::{Gpu, GpuOptions};

/// The scene `main` draws: a duck (ellipsoids) on the ground, after the seed's figure.
pub const SCENE: &str = "duck";
pub const WIDTH: u32 = 160;
pub const HEIGHT: u32 = 120;
/// The ink line's width in pixels (the engine's `--line-width`).
pub const LINE_WIDTH: f32 = 2.0;
/// The ink, linear RGB (the engine's default ink; sRGB 56, 56, 69 in the frame).
pub const INK: Vec4 = Vec4::new(0.04, 0.04, 0.06, 1.0);

/// The cartoon shaders' push constants (`shaders/cartoon_push.glsl`): 112 bytes.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CartoonPush {
    model: Mat4,
    /// rgb: the object's colour or the ink; a: the alpha the draw writes.
    colour: Vec4,
    /// `cartoon_shade`: x toon ramp, y rim ramp, z ink only (all 0: Lambert).
    /// `cartoon_extrude`: x the extrusion in pixels.
    params: Vec4,
    /// The frame in pixels (xy) and the world size of one pixel at unit distance from the eye.
    viewport: Vec4,
}

fn main() -> ExitCode {
    let mut out = String::from("silhouette.png");
    let mut stencil = false;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--stencil" => stencil = true,
            "--out" => match args.next() {
                Some(path) => out = path,
                None => return usage("--out needs a file name"),
            },
            other => return usage(&format!("unknown argument '{other}'")),
        }
    }
    let result = Gpu::new(&GpuOptions::default())
        .and_then(|gpu| render(&gpu, SCENE, stencil))
        .and_then(|frame| nostencil::write_png(&frame, std::path::Path::new(&out), false));
    match result {
        Ok(()) => {
            println!("wrote {out}");
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("silhouette: {error}");
            ExitCode::FAILURE
        }
    }
}

fn usage(problem: &str) -> ExitCode {
    eprintln!("silhouette: {problem}\nusage: silhouette [--out FILE.png] [--stencil]");
    ExitCode::from(2)
}

/// The frame of built-in scene `scene`, inked; with a stencil aspect in the depth attachment
/// when `stencil` (unused: the technique needs none).
pub fn render(gpu: &std::sync::Arc<Gpu>, scene: &str, stencil: bool) -> nostencil::Result<RgbaImage> {
    let base = SampleBase::new(gpu, scene, WIDTH, HEIGHT, stencil)?;
    let device = base.device();
    // Set 2 of the scene pass: the toon and rim ramps `cartoon_shade.frag` declares (unread
    // when it shades Lambert).
    let ramps = base.cartoon_ramps()?;

    // --- The render pass: one subpass, colour and depth.
    let colour = vk::AttachmentDescription::default()
        .format(nostencil::sample::COLOUR_FORMAT)
        .samples(vk::SampleCountFlags::TYPE_1)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .initial_layout(vk::ImageLayout::UNDEFINED)
        .final_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL);
    // Depth (and the reference's unused stencil) live and die in the pass.
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

    // --- The pipelines. Neither blends: the ink only replaces colour.
    use vk::{CompareOp as Cmp, CullModeFlags as Cull};
    // The scene: Lambert over the material (`cartoon_shade`), RGBA replaced (blend off), depth
    // LESS and written, back faces culled.
    let shade = base.pipeline_in(
        ramps.layout,
        &PipelineParts {
            render_pass: pass,
            vertex_shader: "cartoon_shade.vert",
            fragment_shader: "cartoon_shade.frag",
            vertex_input: VertexInput::Scene,
            cull: Cull::BACK,
            depth_test: Some(Cmp::LESS),
            depth_write: true,
            blend: replace(vk::ColorComponentFlags::RGBA),
            stencil: None,
        },
    )?;
    // The inverted hull: the copies in ink (`cartoon_colour.frag`: the push's colour), RGBA
    // replaced (blend off), depth LESS and written, FRONT faces culled: what is left of a copy
    // is its inside, seen only where it is not behind the object.
    let hull = base.pipeline(&PipelineParts {
        render_pass: pass,
        vertex_shader: "cartoon_extrude.vert",
        fragment_shader: "cartoon_colour.frag",
        vertex_input: VertexInput::PositionNormal,
        cull: Cull::FRONT,
        depth_test: Some(Cmp::LESS),
        depth_write: true,
        blend: replace(vk::ColorComponentFlags::RGBA),
        stencil: None,
    })?;

    // Each object's copy: its mesh welded by position (no seam cracks it open when pushed), one
    // smooth normal per vertex.
    let copies = (0..base.scene.objects.len())
        .map(|index| {
            let copy = base.smooth_copy(index)?;
            let vertices = base.vertex_buffer("copy vertices", &copy.vertices)?;
            Ok((vertices, base.vertex_buffer("copy indices", &copy.indices)?, copy.indices.len() as u32))
        })
        .collect::<nostencil::Result<Vec<_>>>()?;
    // What turns pixels into a distance: one pixel at unit distance from the eye spans
    // 2 tan(fov / 2) / height; the vertex shader scales it by the vertex's distance.
    let pixel = 2.0 * (0.5 * base.scene.camera.fov_y_radians).tan() / HEIGHT as f32;
    let viewport = Vec4::new(WIDTH as f32, HEIGHT as f32, pixel, 0.0);
    let bind = |cmd: vk::CommandBuffer, pipeline: vk::Pipeline| {
        // SAFETY: `cmd` is recording in the pass.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline) };
    };

    // --- The draws, in order.
    base.render(|cmd| {
        let background = base.scene.background;
        let clear = [
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
        // 1. The scene, Lambert: params 0 (no toon, no rim), pushed once whole; each object
        // then pushes its transform and colour (alpha 1) over the first 80 bytes.
        bind(cmd, shade);
        // Set 0 first (with the base's layout), then set 2: binding set 0 again (`draw_objects`)
        // with a layout that agrees on it leaves set 2 bound.
        base.bind_frame_uniforms(cmd);
        ramps.bind(cmd);
        let lambert = CartoonPush { model: Mat4::IDENTITY, colour: Vec4::ONE, params: Vec4::ZERO, viewport };
        base.push(cmd, bytemuck::bytes_of(&lambert));
        base.draw_objects(cmd, 1.0, |_| true);
        // 2. The ink: every object's copy, in scene order, pushed out by the line width.
        bind(cmd, hull);
        for (object, (vertices, indices, count)) in base.scene.objects.iter().zip(&copies) {
            let push = CartoonPush {
                model: object.transform,
                colour: INK,
                params: Vec4::new(LINE_WIDTH, 0.0, 0.0, 0.0),
                viewport,
            };
            base.push(cmd, bytemuck::bytes_of(&push));
            // SAFETY: `cmd` is recording in the pass with the hull bound; the buffers live until
            // `render` returns.
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
