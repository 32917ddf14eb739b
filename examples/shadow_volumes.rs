//! Shadow volumes counted in the alpha channel (seed 000, Hall's "Creating Stencil Shadows on
//! iPhone"), in one file read top to bottom: the frame's render pass, its pipelines with each
//! blend state's formula, and its draws in order.
//!
//!     cargo run --example shadow_volumes -- [--out FILE.png] [--stencil]
//!
//! `--stencil` draws the same frame with a real stencil, the way a port with one would ship it;
//! `cargo test` proves both images equal, and equal to the engine's (`nostencil render --scene
//! box --samples 1 --shadow-mode modulate --normalize seed --unclipped-volumes`).
//!
//! The frame (docs/design/shadow-volumes.md has the maths):
//! 1. the lit scene, writing alpha 0: the counter starts at 0 on every pixel;
//! 2. each caster's volume, extruded from its silhouette away from the light: z-pass counts
//!    the walls in front of the visible surface, z-fail (when the camera is inside a volume)
//!    those behind it, with caps. Alpha goes up by k/255 per wall entered, down per wall left;
//! 3. the count normalised by blending alone: 0 becomes 1, any other count D;
//! 4. the colour multiplied by alpha.
//!
//! What the engine adds on top (clipping, culling, GPU extrusion, the additive light loop) is
//! in docs/porting.md, each with what it saves.

use std::process::ExitCode;

use ash::vk;
use glam::{Mat4, Vec4};
use image::RgbaImage;
use nostencil::sample::{blend, replace, stencil_face, PipelineParts, SampleBase, VertexInput};
use nostencil::Gpu;

/// The scene `main` draws: one box over the ground under a directional light.
pub const SCENE: &str = "box";
pub const WIDTH: u32 = 160;
pub const HEIGHT: u32 = 120;
/// k: alpha added per volume wall, in 1/255 steps. A pixel can count 255 / k walls.
const K: u8 = 1;
/// D: a shadowed pixel's colour is multiplied by D / 255.
const DARKNESS: u8 = 102;
/// The stencil's zero, for the reference: a count that goes below it stays lit.
const STENCIL_ZERO: u32 = 0x80;

/// The volume shader's push constants (`shaders/volume_push.glsl`): 128 bytes.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct VolumePush {
    model: Mat4,
    /// a: what one wall adds (k/255).
    colour: Vec4,
    /// The light in the caster's space: direction (w = 0) or position (w = 1).
    light: Vec4,
    /// Unused here: the GPU-skinned caster's centroid, the GPU-extrusion table, the flags (0:
    /// w = 0 vertices go to infinity) and a bounded reach.
    apex: Vec4,
    mesh: u32,
    flags: u32,
    reach: f32,
    unused: u32,
}

/// One caster's volume: doubled vertices (`[p, 1]` then `[p, 0]`, the second pushed to
/// infinity away from the light by `shadow_volume.vert`) and its triangles.
struct Volume {
    object: usize,
    vertices: Vec<Vec4>,
    sides: Vec<u32>,
    caps: Vec<u32>,
}

fn main() -> ExitCode {
    nostencil::sample::run("shadow_volumes", |gpu, stencil| render(gpu, SCENE, stencil))
}

/// The frame of built-in scene `scene`, with the alpha counter, or a real stencil when `stencil`.
pub fn render(gpu: &std::sync::Arc<Gpu>, scene: &str, stencil: bool) -> nostencil::Result<RgbaImage> {
    let base = SampleBase::new(gpu, scene, WIDTH, HEIGHT, stencil)?;
    let device = base.device();
    // z-pass breaks when the near plane cuts a volume: then z-fail, for the whole frame.
    let zfail = base.camera_in_a_volume();
    let volumes = build_volumes(&base, zfail)?;

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
    let (rgba, rgb, a) = (
        vk::ColorComponentFlags::RGBA,
        vk::ColorComponentFlags::R | vk::ColorComponentFlags::G | vk::ColorComponentFlags::B,
        vk::ColorComponentFlags::A,
    );
    use vk::{BlendFactor as F, BlendOp as Op, CompareOp as Cmp, CullModeFlags as Cull};
    // The lit scene: Lambert + ambient, alpha = the push's (0: the counter's start).
    let lit = base.pipeline(&PipelineParts {
        render_pass: pass,
        vertex_shader: "lit.vert",
        fragment_shader: "lit.frag",
        vertex_input: VertexInput::Scene,
        cull: Cull::BACK,
        depth_test: Some(Cmp::LESS),
        depth_write: true,
        blend: replace(rgba),
        stencil: None,
    })?;
    let volume = PipelineParts {
        render_pass: pass,
        vertex_shader: "shadow_volume.vert",
        fragment_shader: "shadow_volume.frag",
        vertex_input: VertexInput::Position4,
        // No depth write: the volumes only count.
        depth_test: Some(if zfail { Cmp::GREATER_OR_EQUAL } else { Cmp::LESS }),
        ..PipelineParts::default()
    };
    // Increment: dst.a = dst.a + k/255 (ADD, ONE, ONE), alpha only. z-pass: the front faces
    // in front of the surface; z-fail: the back faces behind it.
    let increment = base.pipeline(&PipelineParts {
        cull: if zfail { Cull::FRONT } else { Cull::BACK },
        blend: blend(Op::ADD, F::ONE, F::ONE, a),
        ..volume
    })?;
    // Decrement: dst.a = dst.a - k/255 (REVERSE_SUBTRACT, ONE, ONE), clamped at 0. A real
    // stencil wraps, alpha clamps: every increment is drawn before any decrement.
    let decrement = base.pipeline(&PipelineParts {
        cull: if zfail { Cull::BACK } else { Cull::FRONT },
        blend: blend(Op::REVERSE_SUBTRACT, F::ONE, F::ONE, a),
        ..volume
    })?;
    // The reference: both faces in one draw, the stencil counting (it wraps, so any order).
    let (front, back) = if zfail {
        (vk::StencilOp::DECREMENT_AND_WRAP, vk::StencilOp::INCREMENT_AND_WRAP)
    } else {
        (vk::StencilOp::INCREMENT_AND_WRAP, vk::StencilOp::DECREMENT_AND_WRAP)
    };
    let counting_face = |op| {
        let mut face = stencil_face(Cmp::ALWAYS, 0, vk::StencilOp::KEEP);
        if zfail {
            face.depth_fail_op = op
        } else {
            face.pass_op = op
        }
        face
    };
    let stencil_volumes = base.pipeline(&PipelineParts {
        depth_test: Some(Cmp::LESS),
        blend: replace(vk::ColorComponentFlags::empty()),
        stencil: Some((counting_face(front), counting_face(back))),
        ..volume
    })?;
    // Full-screen passes (`fullscreen.vert` + `solid.frag`: the push's colour), alpha only.
    // N0: dst.a = (1 - dst.a) * 1 - dst.a * 1 = 1 - 2a (SUBTRACT, ONE_MINUS_DST_ALPHA, ONE).
    // Lit (0) becomes 1; one wall becomes 1 - 2/255; deep counts clamp to 0.
    let n0 = base.pipeline(&PipelineParts {
        render_pass: pass,
        blend: blend(Op::SUBTRACT, F::ONE_MINUS_DST_ALPHA, F::ONE, a),
        ..PipelineParts::default()
    })?;
    // Iteration: dst.a = a * a - (1 - a) (REVERSE_SUBTRACT, ONE_MINUS_DST_ALPHA, DST_ALPHA).
    // 1 stays 1; the distance d = 1 - a from 1 grows to 3d - d^2: every count falls to 0.
    let iteration = base.pipeline(&PipelineParts {
        render_pass: pass,
        blend: blend(Op::REVERSE_SUBTRACT, F::ONE_MINUS_DST_ALPHA, F::DST_ALPHA, a),
        ..PipelineParts::default()
    })?;
    // Darkness: dst.a = a - D (REVERSE_SUBTRACT, ONE, ONE), then a + D (ADD, ONE, ONE):
    // 0 becomes D, 1 returns to 1.
    let minus_d = base.pipeline(&PipelineParts {
        render_pass: pass,
        blend: blend(Op::REVERSE_SUBTRACT, F::ONE, F::ONE, a),
        ..PipelineParts::default()
    })?;
    let plus_d = base.pipeline(&PipelineParts {
        render_pass: pass,
        blend: blend(Op::ADD, F::ONE, F::ONE, a),
        ..PipelineParts::default()
    })?;
    // Apply: dst.rgb = src.rgb * 0 + dst.rgb * dst.a (ADD, ZERO, DST_ALPHA), colour only.
    let apply = base.pipeline(&PipelineParts {
        render_pass: pass,
        blend: blend(Op::ADD, F::ZERO, F::DST_ALPHA, rgb),
        ..PipelineParts::default()
    })?;
    // The reference's apply: dst.rgb = dst.rgb * D where 0x80 < stencil (ADD, ZERO, SRC_COLOR).
    let stencil_apply = base.pipeline(&PipelineParts {
        render_pass: pass,
        blend: blend(Op::ADD, F::ZERO, F::SRC_COLOR, rgb),
        stencil: Some((
            stencil_face(Cmp::LESS, STENCIL_ZERO, vk::StencilOp::KEEP),
            stencil_face(Cmp::LESS, STENCIL_ZERO, vk::StencilOp::KEEP),
        )),
        ..PipelineParts::default()
    })?;

    // The volumes' vertices and indices, one buffer each per caster.
    let buffers = volumes
        .iter()
        .map(|v| {
            let indices: Vec<u32> = v.sides.iter().chain(&v.caps).copied().collect();
            Ok((base.vertex_buffer("volume vertices", &v.vertices)?, base.vertex_buffer("volume indices", &indices)?))
        })
        .collect::<nostencil::Result<Vec<_>>>()?;
    let draw_volumes = |cmd: vk::CommandBuffer| {
        base.bind_frame_uniforms(cmd);
        for (v, (vertices, indices)) in volumes.iter().zip(&buffers) {
            let object = &base.scene.objects[v.object];
            let push = VolumePush {
                model: object.transform,
                colour: Vec4::new(0.0, 0.0, 0.0, K as f32 / 255.0),
                light: base.light_in_object_space(object),
                apex: Vec4::ZERO,
                mesh: 0,
                flags: 0,
                reach: 0.0,
                unused: 0,
            };
            base.push(cmd, bytemuck::bytes_of(&push));
            let count = (v.sides.len() + v.caps.len()) as u32;
            // SAFETY: `cmd` is recording in the pass with a volume pipeline bound; the buffers
            // live until `render` returns. First instance 1: the shader's weight (one count).
            unsafe {
                device.cmd_bind_vertex_buffers(cmd, 0, &[vertices.raw()], &[0]);
                device.cmd_bind_index_buffer(cmd, indices.raw(), 0, vk::IndexType::UINT32);
                device.cmd_draw_indexed(cmd, count, 1, 0, 0, 1);
            }
        }
    };
    let solid = |cmd: vk::CommandBuffer, pipeline: vk::Pipeline, colour: [f32; 4]| {
        base.push(cmd, bytemuck::bytes_of(&colour));
        // SAFETY: `cmd` is recording in the pass; one triangle covers the frame.
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            device.cmd_draw(cmd, 3, 1, 0, 0);
        }
    };
    let bind = |cmd: vk::CommandBuffer, pipeline: vk::Pipeline| {
        // SAFETY: `cmd` is recording in the pass.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline) };
    };
    let d = DARKNESS as f32 / 255.0;
    let iterations = iterations(K, DARKNESS);

    // --- The draws, in order.
    base.render(|cmd| {
        let background = base.scene.background;
        let clear = [
            // Alpha 0: the counter's start where nothing is drawn.
            vk::ClearValue { color: vk::ClearColorValue { float32: background.extend(0.0).to_array() } },
            vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: STENCIL_ZERO } },
        ];
        let begin = vk::RenderPassBeginInfo::default()
            .render_pass(pass)
            .framebuffer(framebuffer)
            .render_area(vk::Rect2D { offset: vk::Offset2D::default(), extent: base.extent })
            .clear_values(&clear);
        // SAFETY: `cmd` is recording; the pass and framebuffer are the base's.
        unsafe { device.cmd_begin_render_pass(cmd, &begin, vk::SubpassContents::INLINE) };
        base.whole_frame(cmd);
        // 1. The lit scene, alpha 0.
        bind(cmd, lit);
        base.draw_objects(cmd, 0.0, |_| true);
        if stencil {
            // 2. The volumes count in the stencil; 4. where it is above zero, darken.
            bind(cmd, stencil_volumes);
            draw_volumes(cmd);
            solid(cmd, stencil_apply, [d, d, d, 0.0]);
        } else {
            // 2. The volumes count in alpha: every increment, then every decrement.
            bind(cmd, increment);
            draw_volumes(cmd);
            bind(cmd, decrement);
            draw_volumes(cmd);
            // 3. The count becomes a mask: 1 where lit, D where shadowed.
            solid(cmd, n0, [0.0, 0.0, 0.0, 1.0]);
            for _ in 0..iterations {
                solid(cmd, iteration, [0.0, 0.0, 0.0, 1.0]);
            }
            solid(cmd, minus_d, [0.0, 0.0, 0.0, d]);
            solid(cmd, plus_d, [0.0, 0.0, 0.0, d]);
            // 4. The colour times the mask.
            solid(cmd, apply, [0.0, 0.0, 0.0, 1.0]);
        }
        // SAFETY: the pass was begun above.
        unsafe { device.cmd_end_render_pass(cmd) };
        Ok(())
    })
}

/// Each caster's volume for the scene's light, in the caster's own space (Everitt and
/// Kilgard's construction): a wall for every silhouette edge (lit face on one side, unlit on
/// the other), and for z-fail the caps that close it: the lit faces (near) and the lit faces
/// pushed to infinity, reversed (far; for a directional light every point at infinity is one
/// point, so the far cap has no area and is left out). Closed, consistently wound casters only:
/// the engine also casts open and non-manifold meshes, two-sided (docs/porting.md).
fn build_volumes(base: &SampleBase, zfail: bool) -> nostencil::Result<Vec<Volume>> {
    let mut volumes = Vec::new();
    for (object_index, object) in base.scene.objects.iter().enumerate().filter(|(_, o)| o.casts_shadow) {
        let (positions, triangles) = base.welded_mesh(object)?;
        let light = base.light_in_object_space(object);
        // A face is lit when it faces the light (its normal against the light's travel).
        let lit: Vec<bool> = triangles
            .iter()
            .map(|&[a, b, c]| {
                let [a, b, c] = [a, b, c].map(|i| positions[i as usize]);
                let normal = (b - a).cross(c - a);
                let toward_light = if light.w == 0.0 { -light.truncate() } else { light.truncate() - a };
                normal.dot(toward_light) > 0.0
            })
            .collect();
        let n = positions.len() as u32;
        let far = |v: u32| n + v;
        // Directed edge a -> b of a lit face: its wall runs b -> a, so that every edge of the
        // closed volume is matched by its reverse and its faces point out.
        let edges = |[a, b, c]: [u32; 3]| [(a, b), (b, c), (c, a)];
        let unlit_edges: std::collections::HashSet<(u32, u32)> =
            triangles.iter().zip(&lit).filter(|(_, &lit)| !lit).flat_map(|(&t, _)| edges(t)).collect();
        let lit_faces = || triangles.iter().zip(&lit).filter(|(_, &lit)| lit).map(|(&t, _)| t);
        let mut sides = Vec::new();
        // A silhouette edge: the face across it (which runs it b -> a) is unlit.
        for (a, b) in lit_faces().flat_map(edges).filter(|&(a, b)| unlit_edges.contains(&(b, a))) {
            sides.extend_from_slice(&[b, a, far(a), b, far(a), far(b)]);
        }
        let mut caps = Vec::new();
        if zfail {
            for [a, b, c] in lit_faces() {
                caps.extend_from_slice(&[a, b, c]);
                if light.w != 0.0 {
                    caps.extend_from_slice(&[far(a), far(c), far(b)]);
                }
            }
        }
        let vertices = positions.iter().map(|p| p.extend(1.0)).chain(positions.iter().map(|p| p.extend(0.0))).collect();
        volumes.push(Volume { object: object_index, vertices, sides, caps });
    }
    Ok(volumes)
}

/// Iterations after N0 that bring every shadowed count to D or below, on any GPU: products
/// rounded up (the worst case Vulkan allows), for every count a pixel can hold (255 / k).
fn iterations(k: u8, darkness: u8) -> usize {
    let up = |a: u32, b: u32| (a * b).div_ceil(255);
    (0..32)
        .find(|&n| {
            (1..=255 / k as u32).all(|count| {
                let a = count * k as u32;
                let mut a = (up(255, 255 - a) as i32 - a as i32).clamp(0, 255) as u32;
                for _ in 0..n {
                    a = (up(a, a) as i32 - up(255, 255 - a) as i32).clamp(0, 255) as u32;
                }
                a <= darkness as u32
            })
        })
        .unwrap_or(32)
}
