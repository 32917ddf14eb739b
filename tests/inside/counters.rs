//! The fill-rate counters are exact and explained: samples passed are exact pixel counts, and
//! fragment shader invocations follow lavapipe's documented rule (docs/design/lavapipe.md):
//! 16 x, for each rasterised triangle, the aligned 4x4 pixel blocks in which it covers at least
//! one pixel centre, depth-rejected blocks included.

use crate::common;

use std::sync::Arc;

use ash::vk;
use glam::{Vec2, Vec4};
use nostencil::gpu::memory::Buffer;
use nostencil::pipeline::{BlendState, DepthState, FixedFunction, PipelineDesc, RasterState, VertexLayout};
use nostencil::render::Pipeline;
use nostencil::render::Renderer;
use nostencil::FrameCounters;
use nostencil::Gpu;
use nostencil::StencilMode;

fn clip_pipeline(gpu: &Arc<Gpu>, renderer: &Renderer, depth: DepthState) -> Pipeline {
    let desc = PipelineDesc {
        name: "clip-space",
        vertex_shader: nostencil::shaders::CLIP_VERT,
        fragment_shader: nostencil::shaders::SOLID_FRAG,
        vertex_layout: VertexLayout::CLIP4,
        fixed: FixedFunction {
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            raster: RasterState::CULL_NONE,
            depth,
            stencil: None,
            blend: BlendState::OPAQUE,
        },
        push_constant_bytes: 16,
    };
    Pipeline::new(gpu, &desc, renderer.targets.render_pass, &[]).expect("pipeline")
}

/// Triangles in pixel coordinates (with a depth) turned into clip-space vertices.
fn to_clip(triangles: &[[Vec2; 3]], depth: f32, width: u32, height: u32) -> Vec<Vec4> {
    triangles
        .iter()
        .flatten()
        .map(|p| Vec4::new(p.x / width as f32 * 2.0 - 1.0, p.y / height as f32 * 2.0 - 1.0, depth, 1.0))
        .collect()
}

/// Renders each list of triangles as its own pass; returns the frame's counters.
fn render_passes(
    gpu: &Arc<Gpu>,
    width: u32,
    height: u32,
    passes: &[(Vec<[Vec2; 3]>, f32)],
    depth: DepthState,
) -> FrameCounters {
    let mut renderer = Renderer::new(gpu, width, height, StencilMode::Emulated, false).expect("renderer");
    let pipeline = clip_pipeline(gpu, &renderer, depth);
    let buffers: Vec<(Buffer, u32)> = passes
        .iter()
        .map(|(tris, z)| {
            let vertices = to_clip(tris, *z, width, height);
            let buffer = Buffer::with_data(gpu, "test triangles", &vertices, vk::BufferUsageFlags::VERTEX_BUFFER)
                .expect("buffer");
            (buffer, vertices.len() as u32)
        })
        .collect();
    let output = renderer
        .render(&common::clip_space_uniforms(), [0.0; 4], |rec| {
            for (i, (buffer, count)) in buffers.iter().enumerate() {
                rec.pass(&format!("pass {i}"), |rec| {
                    rec.bind(&pipeline);
                    rec.push(&pipeline, &Vec4::ONE);
                    rec.bind_vertices(buffer);
                    rec.draw(*count, 1, 0, 0);
                    Ok(())
                })?;
            }
            Ok(())
        })
        .expect("render");
    output.counters
}

fn edge(a: Vec2, b: Vec2, p: Vec2) -> f32 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

/// Pixel centres a triangle covers (test triangles keep every centre off every edge).
fn covers(t: &[Vec2; 3], p: Vec2) -> bool {
    let e = [edge(t[0], t[1], p), edge(t[1], t[2], p), edge(t[2], t[0], p)];
    e.iter().all(|&v| v > 0.0) || e.iter().all(|&v| v < 0.0)
}

/// lavapipe's rule, on the CPU: 16 x the 4x4 blocks in which the triangle covers a pixel centre.
fn lavapipe_fragment_invocations(triangles: &[[Vec2; 3]], width: u32, height: u32) -> u64 {
    let mut total = 0;
    for t in triangles {
        for by in 0..height.div_ceil(4) {
            for bx in 0..width.div_ceil(4) {
                let touched = (0..16).any(|i| {
                    let (x, y) = (bx * 4 + i % 4, by * 4 + i / 4);
                    x < width && y < height && covers(t, Vec2::new(x as f32 + 0.5, y as f32 + 0.5))
                });
                total += touched as u64 * 16;
            }
        }
    }
    total
}

fn exact_pixels(triangles: &[[Vec2; 3]], width: u32, height: u32) -> u64 {
    let mut count = 0;
    for y in 0..height {
        for x in 0..width {
            let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            count += triangles.iter().filter(|t| covers(t, p)).count() as u64;
        }
    }
    count
}

/// A full-screen quad as two triangles that stay inside the viewport (no clipping).
fn fullscreen_quad(width: u32, height: u32) -> Vec<[Vec2; 3]> {
    let (w, h) = (width as f32, height as f32);
    vec![[Vec2::ZERO, Vec2::new(w, 0.0), Vec2::new(w, h)], [Vec2::ZERO, Vec2::new(w, h), Vec2::new(0.0, h)]]
}

#[test]
fn fullscreen_pass_passes_exactly_w_times_h_samples() {
    let gpu = common::gpu();
    for (width, height) in [(256, 256), (200, 120), (97, 61)] {
        let counters = render_passes(&gpu, width, height, &[(fullscreen_quad(width, height), 0.5)], DepthState::OFF);
        let pass = &counters.passes[0];
        assert_eq!(pass.samples_passed, width as u64 * height as u64, "{width}x{height}");
        assert_eq!(pass.draws, 1);
        assert_eq!(pass.vertex_invocations, Some(6));
        assert_eq!(pass.clipping_primitives, Some(2));
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn fullscreen_triangle_matches_the_measured_lavapipe_figures() {
    // docs/design/lavapipe.md: one clipped full-screen triangle reports 66,560 at 256x256 and
    // 927,360 at 1280x720 (lavapipe clips it into triangles and counts the blocks of each).
    let gpu = common::gpu();
    if !common::lavapipe_figures_apply(&gpu, "the measured full-screen figures") {
        return;
    }
    let big = |w: u32, h: u32| vec![[Vec2::ZERO, Vec2::new(2.0 * w as f32, 0.0), Vec2::new(0.0, 2.0 * h as f32)]];
    for (width, height, expected) in [(256u32, 256u32, 66_560u64), (1280, 720, 927_360)] {
        let counters = render_passes(&gpu, width, height, &[(big(width, height), 0.5)], DepthState::OFF);
        assert_eq!(counters.passes[0].fragment_invocations, Some(expected), "{width}x{height}");
        assert_eq!(counters.passes[0].samples_passed, width as u64 * height as u64);
    }
    common::assert_no_validation_messages(&gpu);
}

/// Deterministic pseudo-random triangles whose edges avoid every pixel centre.
fn scattered_triangles(seed: u32, count: usize, width: u32, height: u32) -> Vec<[Vec2; 3]> {
    let mut state = seed.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32
    };
    let mut triangles = Vec::new();
    while triangles.len() < count {
        // Vertices on a 1/16-pixel grid are exact after the rasteriser's sub-pixel snapping.
        let snap = |v: f32| (v * 16.0).round() / 16.0;
        let mut point = || Vec2::new(snap(next() * (width as f32 - 1.0)), snap(next() * (height as f32 - 1.0)));
        let t = [point(), point(), point()];
        let area = edge(t[0], t[1], t[2]).abs();
        let clear_of_centres = (0..height).all(|y| {
            (0..width).all(|x| {
                let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                // Keep every pixel centre at least 1/50 pixel away from every edge.
                (0..3).all(|i| edge(t[i], t[(i + 1) % 3], p).abs() > 0.02 * (t[(i + 1) % 3] - t[i]).length())
            })
        });
        if area > 4.0 && clear_of_centres {
            triangles.push(t);
        }
    }
    triangles
}

#[test]
fn fragment_invocations_follow_the_4x4_block_rule_on_many_shapes() {
    let gpu = common::gpu();
    if !common::lavapipe_figures_apply(&gpu, "the 4x4 block rule's counts") {
        return;
    }
    for (width, height, seed, count) in [(64u32, 64u32, 1u32, 1usize), (64, 64, 2, 5), (128, 96, 3, 12), (50, 70, 4, 8)]
    {
        let triangles = scattered_triangles(seed, count, width, height);
        // One pass per triangle and one with all of them: the rule holds per triangle and sums.
        let mut passes: Vec<(Vec<[Vec2; 3]>, f32)> = triangles.iter().map(|t| (vec![*t], 0.5)).collect();
        passes.push((triangles.clone(), 0.5));
        let counters = render_passes(&gpu, width, height, &passes, DepthState::OFF);
        for (pass, (tris, _)) in counters.passes.iter().zip(&passes) {
            assert_eq!(
                pass.fragment_invocations,
                Some(lavapipe_fragment_invocations(tris, width, height)),
                "{width}x{height} {}",
                pass.name
            );
            assert_eq!(pass.samples_passed, exact_pixels(tris, width, height), "{width}x{height} {}", pass.name);
        }
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn depth_rejected_blocks_still_count_as_invocations() {
    let gpu = common::gpu();
    let (width, height) = (128u32, 128u32);
    let quad = fullscreen_quad(width, height);
    // A near quad writes depth; a far quad behind it is rejected everywhere.
    let counters =
        render_passes(&gpu, width, height, &[(quad.clone(), 0.25), (quad.clone(), 0.75)], DepthState::WRITE_LESS);
    assert_eq!(counters.passes[0].samples_passed, (width * height) as u64);
    assert_eq!(counters.passes[1].samples_passed, 0, "the far quad is behind the near one");
    if common::lavapipe_figures_apply(&gpu, "the counts of depth-rejected blocks") {
        let expected = lavapipe_fragment_invocations(&quad, width, height);
        assert_eq!(counters.passes[0].fragment_invocations, Some(expected));
        assert_eq!(counters.passes[1].fragment_invocations, Some(expected), "rejected blocks are counted");
    }
    common::assert_no_validation_messages(&gpu);
}

#[test]
fn timestamps_are_positive_and_ordered_per_pass() {
    let gpu = common::gpu();
    let (width, height) = (256u32, 256u32);
    let quad = fullscreen_quad(width, height);
    let passes: Vec<_> = (0..4).map(|i| (quad.clone(), 0.1 * i as f32)).collect();
    let counters = render_passes(&gpu, width, height, &passes, DepthState::OFF);
    let mut previous_start = -1.0;
    for pass in &counters.passes {
        assert!(pass.gpu_ms > 0.0, "{}: {} ms", pass.name, pass.gpu_ms);
        assert!(
            pass.start_ms >= 0.0 && pass.start_ms >= previous_start,
            "{} starts before the pass before it",
            pass.name
        );
        previous_start = pass.start_ms;
    }
    // Passes run one after the other: each starts no earlier than the previous one ended.
    for pair in counters.passes.windows(2) {
        assert!(
            pair[1].start_ms + 1e-6 >= pair[0].start_ms + pair[0].gpu_ms,
            "{} overlaps {}",
            pair[1].name,
            pair[0].name
        );
    }
    common::assert_no_validation_messages(&gpu);
}
