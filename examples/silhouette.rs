//! Ink lines found by silhouette edge detection (seed 002, Marshall's "Real-time silhouette
//! edge detection for cartoon rendering", Game Programming Gems 2, 5.1), in one file read top to
//! bottom: the edge list, each edge classified from the eye, the lines drawn as screen-space
//! quads, the frame's render pass and pipelines, and the draws in order.
//!
//!     cargo run --example silhouette -- [--out FILE.png] [--stencil]
//!
//! No pass of this technique needs a stencil, in the engine's reference path or its emulated
//! one: `--stencil` gives the depth attachment its stencil aspect (as `nostencil render
//! --stencil reference` does) and changes nothing else. `cargo test` proves both images equal,
//! and equal to the engine's (`nostencil render --technique silhouette --scene duck --samples 1`,
//! its default `edges` method).
//!
//! The frame:
//! 1. per object, once: the mesh welded by position (a UV or normal split must not open an
//!    edge) and its unique edge list, each edge with the faces on either side (the seed's hash
//!    table);
//! 2. per frame, each edge classified: a *silhouette* where one face looks at the eye and the
//!    other away (`(N1.V)(N2.V) <= 0`), a *crease* where the faces fold by more than 40 degrees,
//!    a *boundary* where it has one face. Each edge is drawn once, in that order of priority;
//! 3. the scene, shaded Lambert (`cartoon_shade`), depth written;
//! 4. each class's edges as quads `LINE_WIDTH` pixels wide, built in the vertex shader from
//!    both projected ends (the mobile profile has no wide lines), depth tested against the
//!    scene after a small pull towards the eye, in ink.
//!
//! What the engine adds on top (attribute seams as boundaries, per-class ink, the N.V rim, the
//! inverted hull, the alpha test) is in docs/porting.md.

use std::process::ExitCode;

use ash::vk;
use glam::{Mat4, Vec2, Vec3, Vec4};
use image::RgbaImage;
use nostencil::sample::{replace, PipelineParts, SampleBase, VertexInput};
use nostencil::Gpu;

/// The scene `main` draws: a duck (ellipsoids) on the ground, after the seed's figure.
pub const SCENE: &str = "duck";
pub const WIDTH: u32 = 160;
pub const HEIGHT: u32 = 120;
/// The ink line's width in pixels (the engine's `--line-width`).
pub const LINE_WIDTH: f32 = 2.0;
/// The ink, linear RGB (the engine's default ink; sRGB 56, 56, 69 in the frame).
pub const INK: Vec4 = Vec4::new(0.04, 0.04, 0.06, 1.0);
/// Edges whose faces fold by more than this are creases (the engine's `--crease-angle`).
const CREASE_DEG: f32 = 40.0;

/// One corner of an ink quad (`shaders/cartoon_ink.vert`): both ends of the edge in world
/// space, the third corner of its front-facing face (a silhouette grows away from it), and
/// which corner: x the side (-1 or +1), y 0 at `a` and 1 at `b`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct InkVertex {
    a: Vec3,
    b: Vec3,
    c: Vec3,
    corner: Vec2,
}

/// The six corners (two triangles) of one edge's quad.
const QUAD: [Vec2; 6] = [
    Vec2::new(-1.0, 0.0),
    Vec2::new(1.0, 0.0),
    Vec2::new(1.0, 1.0),
    Vec2::new(-1.0, 0.0),
    Vec2::new(1.0, 1.0),
    Vec2::new(-1.0, 1.0),
];

/// An edge of a welded mesh: its ends (`v[0] < v[1]`) and the faces that have it (one for a
/// boundary).
struct Edge {
    v: [u32; 2],
    faces: Vec<usize>,
}

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
    nostencil::sample::run("silhouette", |gpu, stencil| render(gpu, SCENE, stencil))
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
    // The ink: quads in the push's colour (`cartoon_colour.frag`), RGB replaced (blend off),
    // depth LESS_OR_EQUAL and not written, no culling (a quad faces either way).
    let ink = base.pipeline(&PipelineParts {
        render_pass: pass,
        vertex_shader: "cartoon_ink.vert",
        fragment_shader: "cartoon_colour.frag",
        vertex_input: VertexInput::Ink,
        cull: Cull::NONE,
        depth_test: Some(Cmp::LESS_OR_EQUAL),
        depth_write: false,
        blend: replace(vk::ColorComponentFlags::R | vk::ColorComponentFlags::G | vk::ColorComponentFlags::B),
        stencil: None,
    })?;

    // The edges of every object, classified from the eye: one list of quads per class.
    let mut classes: [Vec<InkVertex>; 3] = Default::default();
    for object in &base.scene.objects {
        let (positions, triangles) = base.welded_mesh(object)?;
        ink_quads(&positions, &triangles, &object.transform, base.scene.camera.eye, &mut classes);
    }
    let quads = classes
        .iter()
        .map(|quads| Ok((base.vertex_buffer("ink quads", quads)?, quads.len() as u32)))
        .collect::<nostencil::Result<Vec<_>>>()?;
    // What turns pixels into a distance: one pixel at unit distance from the eye spans
    // 2 tan(fov / 2) / height.
    let pixel = 2.0 * (0.5 * base.scene.camera.fov_y_radians).tan() / HEIGHT as f32;
    let viewport = Vec4::new(WIDTH as f32, HEIGHT as f32, pixel, 0.0);
    // The lines are pulled towards the eye by about one line width at any distance (a constant
    // in clip z with the infinite-far projection): enough for a crease between faces tilted up
    // to ~60 degrees, far too little to show through a solid.
    let pull = base.scene.camera.near * (LINE_WIDTH * pixel).max(1e-3);
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
        // 2. The ink, a draw per class: silhouettes grow outwards only (params.y = 1), creases
        // and boundaries are centred on their edge.
        bind(cmd, ink);
        for (class, (buffer, count)) in quads.iter().enumerate() {
            let one_sided = if class == 0 { 1.0 } else { 0.0 };
            let push = CartoonPush {
                model: Mat4::IDENTITY,
                colour: INK,
                params: Vec4::new(LINE_WIDTH, one_sided, pull, 0.0),
                viewport,
            };
            base.push(cmd, bytemuck::bytes_of(&push));
            // SAFETY: `cmd` is recording in the pass with the ink bound; the buffer lives until
            // `render` returns.
            unsafe {
                device.cmd_bind_vertex_buffers(cmd, 0, &[buffer.raw()], &[0]);
                device.cmd_draw(cmd, *count, 1, 0, 0);
            }
        }
        // SAFETY: the pass was begun above.
        unsafe { device.cmd_end_render_pass(cmd) };
        Ok(())
    })
}

/// A welded mesh's unique edges, in the order of their ends, each with its faces in face order
/// (the seed builds this list once per mesh, with a hash table).
fn edge_list(triangles: &[[u32; 3]]) -> Vec<Edge> {
    let mut edges: std::collections::BTreeMap<[u32; 2], Vec<usize>> = Default::default();
    for (face, &[a, b, c]) in triangles.iter().enumerate() {
        for (from, to) in [(a, b), (b, c), (c, a)] {
            edges.entry([from.min(to), from.max(to)]).or_default().push(face);
        }
    }
    edges.into_iter().map(|(v, faces)| Edge { v, faces }).collect()
}

/// The ink quads of one object (its welded `positions` and `triangles`, placed by `model`)
/// seen from `eye`, appended to `classes` (silhouette, crease, boundary): each edge once, in
/// the first class it belongs to.
fn ink_quads(positions: &[Vec3], triangles: &[[u32; 3]], model: &Mat4, eye: Vec3, classes: &mut [Vec<InkVertex>; 3]) {
    // Everything is decided in the object's own space: the eye is taken there.
    let eye = model.inverse().transform_point3(eye);
    let normals: Vec<Vec3> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize]);
            (b - a).cross(c - a).normalize_or_zero()
        })
        .collect();
    let crease_cos = CREASE_DEG.to_radians().cos();
    let world = |v: u32| model.transform_point3(positions[v as usize]);
    for edge in edge_list(triangles) {
        // N.V is the same at every point of a face's plane; the seed uses the edge's first end.
        let to_edge = positions[edge.v[0] as usize] - eye;
        let class = match edge.faces[..] {
            [f1, f2, ..] if normals[f1].dot(to_edge) * normals[f2].dot(to_edge) <= 0.0 => 0,
            [f1, f2, ..] if normals[f1].dot(normals[f2]) < crease_cos => 1,
            [_] => 2,
            _ => continue,
        };
        // The face that looks at the eye, and its corner off the edge.
        let front = match edge.faces[..] {
            [f1, f2, ..] if normals[f1].dot(to_edge) >= 0.0 => f2,
            _ => edge.faces[0],
        };
        let corners = triangles[front];
        let third = corners.into_iter().find(|v| !edge.v.contains(v)).unwrap_or(corners[0]);
        let (a, b, c) = (world(edge.v[0]), world(edge.v[1]), world(third));
        classes[class].extend(QUAD.iter().map(|&corner| InkVertex { a, b, c, corner }));
    }
}
