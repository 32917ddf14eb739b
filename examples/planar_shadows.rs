//! Planar projected shadows with double darkening stopped in alpha (seed 001), in one file
//! read top to bottom: the frame's render pass, its pipelines with each blend state's formula,
//! and its draws in order.
//!
//!     cargo run --example planar_shadows -- [--out FILE.png] [--stencil]
//!
//! `--stencil` draws the same frame with a real stencil, the way a port with one would ship it
//! (the seed's own); `cargo test` proves both images equal, and equal to the engine's
//! (`nostencil render --technique planar --scene overlap --samples 1 --shadow-mode modulate`).
//!
//! The frame (docs/planar-shadows.md, docs/design/planar-shadows.md has the maths):
//! 1. the lit scene: receivers (the ground) write alpha F/255, everything else (and the clear)
//!    alpha 1. Alpha is the flag "a receiver not yet shadowed, and by how much to shadow it";
//! 2. every caster drawn again, flattened onto the ground along the light in the vertex shader,
//!    colour 0, multiplying the pixel by its alpha and setting that alpha to 1: the first
//!    fragment on a receiver darkens it by F/255, every later one (the caster's back faces,
//!    another caster's overlapping shadow) by 1, and fragments on anything but a receiver by 1.
//!
//! One pass, no full-screen quad. What the engine adds on top (GPU skinning, a tilted plane, the
//! additive light loop, simplified casters) is in docs/porting.md.

use std::process::ExitCode;

use ash::vk;
use glam::{Mat4, Vec4};
use image::RgbaImage;
use nostencil::sample::{blend, replace, stencil_face, PipelineParts, SampleBase, VertexInput};
use nostencil::Gpu;

/// The scene `main` draws: stacked boxes whose shadows overlap, a torus and a sphere, over the
/// ground under a directional light.
pub const SCENE: &str = "overlap";
pub const WIDTH: u32 = 160;
pub const HEIGHT: u32 = 120;
/// F: a shadowed receiver's colour is multiplied by F / 255 (an 8-bit value, so that both paths
/// multiply by the same number).
const FACTOR: u8 = 102;
/// The reference's stencil: 0 under a receiver not yet shadowed, 1 anywhere else.
const STENCIL_RECEIVER: u32 = 0;
const STENCIL_OTHER: u32 = 1;
/// Depth bias of the flattened casters (constant, slope), towards the camera: they lie in the
/// ground's plane and must win LESS_OR_EQUAL against it (same plane, different triangles:
/// their depths differ in the last bits), while anything standing on the ground still hides them.
const SHADOW_BIAS: (f32, f32) = (-4.0, -1.5);

/// The flattening shader's push constants (`shaders/planar_push.glsl`): 112 bytes. The first 80
/// are laid out as `object_push.glsl`'s, which `object_colour.frag` reads.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PlanarPush {
    model: Mat4,
    /// The shadow's colour: rgb 0; alpha 1 (alpha path) or F/255 (stencil path).
    colour: Vec4,
    /// The receiving plane (n, d): n.x + d = 0, n unit, pointing to the casters' side.
    plane: Vec4,
    /// x: the index of the light the shadow is cast from in the frame's uniforms.
    light: [u32; 4],
}

fn main() -> ExitCode {
    nostencil::sample::run("planar_shadows", |gpu, stencil| render(gpu, SCENE, stencil))
}

/// The frame of built-in scene `scene`, with the alpha flag, or a real stencil when `stencil`.
pub fn render(gpu: &std::sync::Arc<Gpu>, scene: &str, stencil: bool) -> nostencil::Result<RgbaImage> {
    let base = SampleBase::new(gpu, scene, WIDTH, HEIGHT, stencil)?;
    let device = base.device();
    // The ground: its plane, and which objects lie in it (they receive; all others cast).
    let ground = base.ground()?;
    let light = base.scene.primary_light_index().unwrap_or(0) as u32;

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
    let rgba = vk::ColorComponentFlags::RGBA;
    use vk::{BlendFactor as F, BlendOp as Op, CompareOp as Cmp, CullModeFlags as Cull};
    // The lit scene: Lambert + ambient, alpha = the push's (F/255 on receivers, else 1).
    let lit_parts = PipelineParts {
        render_pass: pass,
        vertex_shader: "lit.vert",
        fragment_shader: "lit.frag",
        vertex_input: VertexInput::Scene,
        cull: Cull::BACK,
        depth_test: Some(Cmp::LESS),
        depth_write: true,
        blend: replace(rgba),
        stencil: None,
    };
    let lit = base.pipeline(&lit_parts)?;
    // The reference marks receivers in the stencil: 0 under them, 1 under everything else.
    let mark = |value| {
        let face = stencil_face(Cmp::ALWAYS, value, vk::StencilOp::REPLACE);
        base.pipeline(&PipelineParts { stencil: Some((face, face)), ..lit_parts })
    };
    let (stencil_receivers, stencil_others) = (mark(STENCIL_RECEIVER)?, mark(STENCIL_OTHER)?);
    // The casters flattened onto the plane (`planar_shadow.vert`; `object_colour.frag` writes the
    // push's colour). Flattened, front and back faces both land on the plane: no culling, both
    // drawn, which is exactly the overlap the blend (or the stencil) must not count twice.
    let shadow = PipelineParts {
        render_pass: pass,
        vertex_shader: "planar_shadow.vert",
        fragment_shader: "object_colour.frag",
        vertex_input: VertexInput::Scene,
        cull: Cull::NONE,
        depth_test: Some(Cmp::LESS_OR_EQUAL),
        ..PipelineParts::default()
    };
    // Modulate once: dst.rgb = src.rgb * 0 + dst.rgb * dst.a (ADD, ZERO, DST_ALPHA), then
    // dst.a = src.a * 1 + dst.a * 0 = 1 (ADD, ONE, ZERO). A receiver's first fragment multiplies
    // it by F/255 and sets its alpha to 1; every later one multiplies by 1.
    let modulate_once = base.pipeline_with_depth_bias(
        &PipelineParts {
            blend: blend(Op::ADD, F::ZERO, F::DST_ALPHA, rgba)
                .src_alpha_blend_factor(F::ONE)
                .dst_alpha_blend_factor(F::ZERO),
            ..shadow
        },
        SHADOW_BIAS.0,
        SHADOW_BIAS.1,
    )?;
    // The reference: dst.rgb = dst.rgb * src.a (ADD, ZERO, SRC_ALPHA), dst.a = src.a (ADD, ONE,
    // ZERO), where the stencil is 0 (EQUAL 0), which it increments: one fragment per pixel.
    let once = stencil_face(Cmp::EQUAL, STENCIL_RECEIVER, vk::StencilOp::INCREMENT_AND_WRAP);
    let stencil_modulate = base.pipeline_with_depth_bias(
        &PipelineParts {
            blend: blend(Op::ADD, F::ZERO, F::SRC_ALPHA, rgba)
                .src_alpha_blend_factor(F::ONE)
                .dst_alpha_blend_factor(F::ZERO),
            stencil: Some((once, once)),
            ..shadow
        },
        SHADOW_BIAS.0,
        SHADOW_BIAS.1,
    )?;

    let bind = |cmd: vk::CommandBuffer, pipeline: vk::Pipeline| {
        // SAFETY: `cmd` is recording in the pass.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline) };
    };
    let f = FACTOR as f32 / 255.0;
    let receives = |index: usize| ground.receivers[index];

    // --- The draws, in order.
    base.render(|cmd| {
        let background = base.scene.background;
        let clear = [
            // Alpha 1 where nothing is drawn: not a receiver.
            vk::ClearValue { color: vk::ClearColorValue { float32: background.extend(1.0).to_array() } },
            vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: STENCIL_OTHER } },
        ];
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(pass)
            .framebuffer(framebuffer)
            .render_area(vk::Rect2D { offset: vk::Offset2D::default(), extent: base.extent })
            .clear_values(&clear);
        // SAFETY: `cmd` is recording; the pass and framebuffer are the base's.
        unsafe { device.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE) };
        base.whole_frame(cmd);
        // 1. The lit scene: receivers with alpha F/255 (reference: stencil 0), the rest alpha 1
        //    (reference: stencil 1).
        bind(cmd, if stencil { stencil_receivers } else { lit });
        base.draw_objects_with(cmd, |i, object| receives(i).then(|| base.object_push(object, f)));
        bind(cmd, if stencil { stencil_others } else { lit });
        base.draw_objects_with(cmd, |i, object| (!receives(i)).then(|| base.object_push(object, 1.0)));
        // 2. Every caster flattened onto the ground, black: alpha 1 multiplies by the pixel's
        //    alpha once (the reference's alpha F/255 multiplies where the stencil lets it).
        bind(cmd, if stencil { stencil_modulate } else { modulate_once });
        let alpha = if stencil { f } else { 1.0 };
        base.draw_objects_with(cmd, |i, object| {
            let push = PlanarPush {
                model: object.transform,
                colour: Vec4::new(0.0, 0.0, 0.0, alpha),
                plane: ground.plane,
                light: [light, 0, 0, 0],
            };
            (!receives(i)).then(|| bytemuck::bytes_of(&push).to_vec())
        });
        // SAFETY: the pass was begun above.
        unsafe { device.cmd_end_render_pass(cmd) };
        Ok(())
    })
}
