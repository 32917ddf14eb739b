//! MSAA proven sample by sample (docs/design/msaa.md): the multisampled colour read back
//! before its resolve, the alpha counter equal to the real stencil's count (times k) in every
//! sample, shadow edges with intermediate resolved values, the box's shadow still its projected
//! outline at 4x, and saturation counted per sample.

use crate::common::{self, technique};

use nostencil::ShadowMode;

use std::sync::Arc;

use ash::vk;
use glam::Vec4;
use nostencil::frame::FrameTargets;
use nostencil::gpu::memory::Buffer;
use nostencil::mesh::caster::CastPath;
use nostencil::mesh::Reach;
use nostencil::pipeline::recipes::{both_faces, stencil_face, ALPHA_ONLY, STENCIL_COUNT_ZERO};
use nostencil::pipeline::{BlendState, FixedFunction, PipelineDesc, VertexLayout};
use nostencil::render::passes::Passes;
use nostencil::render::plan::{PassPlan, PlannedPass, SetRole, Target};
use nostencil::render::plan_execution::{record_plan, PlanPipelines};
use nostencil::render::Renderer;
use nostencil::render::{
    FrameRecorder, FrameSamples, FrameUniforms, GpuScene, IndexedDraw, ObjectPush, Pipeline, PipelineTarget,
};
use nostencil::technique::shadow_volume::recipes::{VolumeDraw, VolumeKinds};
use nostencil::technique::shadow_volume::{self, bounds, build_volume, prepare_casters};
use nostencil::technique::shadow_volume::{Normalize, ShadowVolumeOptions, VolumeMethod};
use nostencil::technique::ShadowTone;
use nostencil::Gpu;
use nostencil::RenderOptions;
use nostencil::StencilMode;
use nostencil::{builtin_scene, Scene};

const SAMPLES: u32 = 4;

/// A shadow-volume frame at 4x that keeps its samples, and every sample read back.
fn kept_frame(gpu: &Arc<Gpu>, scene: &Scene, options: RenderOptions) -> (nostencil::FrameOutput, FrameSamples) {
    let options = RenderOptions { samples: SAMPLES, keep_samples: true, ..options };
    let mut renderer = options.technique.build(gpu, scene, &options).expect("renderer");
    let frame = renderer.frame_with(scene).expect("frame");
    let samples = renderer.renderer_mut().read_samples().expect("samples read back");
    (frame.output, samples)
}

#[test]
fn every_sample_is_read_back_and_resolves_to_the_frame() {
    let gpu = common::gpu();
    let scene = builtin_scene("box").expect("scene");
    let options = RenderOptions {
        width: 96,
        height: 64,
        technique: technique("shadow-volume"),
        shadow_volume: ShadowVolumeOptions { normalize: Normalize::Subpass, ..Default::default() },
        ..Default::default()
    };
    let (output, samples) = kept_frame(&gpu, &scene, options.clone());
    assert_eq!((samples.width, samples.height, samples.samples), (96, 64, SAMPLES));
    let (mut uniform, mut mixed) = (0, 0);
    for y in 0..samples.height {
        for x in 0..samples.width {
            let pixel = samples.pixel(x, y);
            let resolved = output.image.get_pixel(x, y).0;
            if pixel.iter().all(|s| *s == pixel[0]) {
                // Every sample alike: the resolve is that sample, byte for byte (so the
                // read-back returns the stored sRGB bytes, not a re-rounded linear value).
                assert_eq!(pixel[0], resolved, "pixel ({x}, {y})");
                uniform += 1;
            } else {
                // Edges: the resolve averages the samples (RGB in linear light, alpha as is).
                mixed += 1;
                for c in 0..3 {
                    let mean = pixel.iter().map(|s| nostencil::frame::srgb::decode(s[c])).sum::<f32>() / 4.0;
                    let expected = nostencil::frame::srgb::encode(mean);
                    assert!(resolved[c].abs_diff(expected) <= 1, "({x}, {y}) channel {c}: {pixel:?} -> {resolved:?}");
                }
                let mean = pixel.iter().map(|s| s[3] as f32).sum::<f32>() / 4.0;
                assert!((resolved[3] as f32 - mean).abs() <= 1.0, "({x}, {y}) alpha: {pixel:?} -> {resolved:?}");
            }
        }
    }
    assert!(uniform > 4000 && mixed > 50, "{uniform} uniform and {mixed} edge pixels");

    // A frame that left its samples in tile memory cannot be read back: a clear error.
    let transient = RenderOptions { samples: SAMPLES, ..options };
    let mut renderer = transient.technique.build(&gpu, &scene, &transient).expect("renderer");
    renderer.frame_with(&scene).expect("frame");
    let error = renderer.renderer_mut().read_samples().expect_err("no samples kept").to_string();
    assert!(error.contains("keep_samples"), "{error}");
    // Nor can a frame that was never drawn.
    let targets =
        FrameTargets::with_samples(&gpu, 16, 16, StencilMode::Emulated, false, SAMPLES, true).expect("targets");
    let mut fresh = Renderer::with_targets(&gpu, targets).expect("renderer");
    let error = fresh.read_samples().expect_err("no frame yet").to_string();
    assert!(error.contains("no frame"), "{error}");
    common::assert_no_validation_messages(&gpu);
}

// ---------------------------------------------------------------------------------------------
// The per-sample proof: the alpha counter against the real stencil, before any normalisation.

/// The largest count the reference makes visible one value at a time; a count above it shows
/// as alpha 255, which no emulated count below the clamp equals.
const SHOWN_COUNTS: u32 = 12;

/// A full-screen pass writing alpha `value` where the stencil passes `compare` against
/// `reference`: per-sample stencil test, so per-sample write.
fn stencil_to_alpha(
    name: &'static str,
    compare: vk::CompareOp,
    reference: u32,
    value: u32,
) -> PlannedPass<VolumeKinds> {
    let desc = PipelineDesc {
        name,
        vertex_shader: nostencil::shaders::FULLSCREEN_VERT,
        fragment_shader: nostencil::shaders::SOLID_FRAG,
        vertex_layout: VertexLayout::NONE,
        fixed: FixedFunction {
            stencil: Some(both_faces(stencil_face(compare, reference, 0, vk::StencilOp::KEEP, vk::StencilOp::KEEP))),
            blend: BlendState { colour: None, alpha: None, write_mask: ALPHA_ONLY },
            ..FixedFunction::FULLSCREEN
        },
        push_constant_bytes: 16,
    };
    PlannedPass::full_screen(name, desc, Vec4::new(0.0, 0.0, 0.0, value as f32 / 255.0))
}

/// One caster's volume on the GPU, unclipped by any scissor.
struct Volume {
    object: usize,
    vertices: Buffer,
    indices: Buffer,
    count: u32,
}

/// The scene's meshes and volumes, drawn as the shadow-volume renderer draws them (every
/// increment, then every decrement), over the whole frame.
struct VolumeDraws<'a> {
    scene: &'a Scene,
    meshes: GpuScene,
    volumes: Vec<Volume>,
}

impl<'a> VolumeDraws<'a> {
    fn new(gpu: &Arc<Gpu>, scene: &'a Scene, zfail: bool) -> Self {
        let (casters, warnings) = prepare_casters(scene);
        assert!(warnings.is_empty(), "{warnings:?}");
        let boxes = bounds::object_boxes(scene);
        let receivers = bounds::receivers_box(&boxes).expect("receivers");
        let volumes = casters
            .iter()
            .map(|caster| {
                let caster_box = boxes[caster.object].expect("caster bounds");
                let reach = bounds::caster_bounds(&scene.light(), caster_box, receivers).reach;
                assert!(!matches!(reach, Reach::Infinite), "a clipped volume");
                let volume = build_volume(scene, caster, reach, true);
                let mut indices = volume.sides.clone();
                // As the renderer: near caps for z-fail and for two-sided casters.
                if zfail || matches!(caster.mesh.path, CastPath::TwoSided { .. }) {
                    indices.extend_from_slice(&volume.near_cap);
                }
                indices.extend_from_slice(&volume.far_cap);
                // This test's counter is a stencil: repeated walls as copies.
                indices.extend(volume.repeated_copies());
                let usage = vk::BufferUsageFlags::VERTEX_BUFFER;
                Volume {
                    object: caster.object,
                    vertices: Buffer::with_data(gpu, "volume vertices", &volume.vertices, usage).expect("vertices"),
                    indices: Buffer::with_data(gpu, "volume indices", &indices, vk::BufferUsageFlags::INDEX_BUFFER)
                        .expect("indices"),
                    count: indices.len() as u32,
                }
            })
            .collect();
        VolumeDraws { scene, meshes: GpuScene::upload(gpu, scene).expect("meshes"), volumes }
    }
}

impl Passes<VolumeKinds> for VolumeDraws<'_> {
    fn meshes(&self) -> Option<&GpuScene> {
        Some(&self.meshes)
    }

    fn draw(
        &self,
        rec: &mut FrameRecorder,
        _: &Scene,
        draw: VolumeDraw,
        _: &PlannedPass<VolumeKinds>,
        pipelines: &[&Pipeline],
    ) -> nostencil::Result<()> {
        let VolumeDraw::Volumes { alpha, .. } = draw;
        for (index, pipeline) in pipelines.iter().enumerate() {
            if index > 0 {
                rec.bind(pipeline);
            }
            for volume in &self.volumes {
                let model = self.scene.objects[volume.object].transform;
                rec.push(pipeline, &ObjectPush { model, colour: Vec4::new(0.0, 0.0, 0.0, alpha) });
                // The volume pipelines count each fragment as many times as the draw's first
                // instance says (a range's multiplicity); every copy here counts once.
                rec.bind_indexed(&volume.vertices, &volume.indices);
                rec.draw_indexed(IndexedDraw { first_instance: 1, ..IndexedDraw::range(0, volume.count) });
            }
        }
        Ok(())
    }

    /// The scene is static and its volumes were built once, by `new`.
    fn prepare(&mut self, _: &Renderer, _: &Scene) -> nostencil::Result<()> {
        Ok(())
    }
}

/// The plan's scene and volume passes at 4x in `stencil`'s path; the reference then shows each
/// sample's count v (the stencil at 0x80 + v) as alpha v x k / 255. Every sample read back.
fn counts_per_sample(
    gpu: &Arc<Gpu>,
    scene: &Scene,
    stencil: StencilMode,
    options: ShadowVolumeOptions,
) -> FrameSamples {
    let (width, height) = (128, 96);
    let targets = FrameTargets::with_samples(gpu, width, height, stencil, false, SAMPLES, true).expect("targets");
    let mut renderer = Renderer::with_targets(gpu, targets).expect("renderer");
    renderer.stencil_clear = STENCIL_COUNT_ZERO;
    let full = shadow_volume::recipes::plan(
        &options,
        nostencil::ShadowMode::Modulate,
        ShadowTone::default(),
        stencil,
        SAMPLES,
        &nostencil::technique::light_loop::PlannedLight::default_lights(),
    )
    .expect("plan");
    let volumes = full.passes.iter().position(|p| p.name.starts_with("volumes")).expect("volume pass");
    let mut plan = PassPlan::new();
    plan.extend(full.passes[..=volumes].iter().cloned());
    if stencil == StencilMode::Reference {
        let k = u32::from(options.increment);
        for v in 1..=SHOWN_COUNTS {
            let name: &'static str = Box::leak(format!("stencil count {v}").into_boxed_str());
            plan.push(stencil_to_alpha(name, vk::CompareOp::EQUAL, STENCIL_COUNT_ZERO + v, v * k));
        }
        // `reference < stencil`: a count above those shown.
        plan.push(stencil_to_alpha("stencil count above", vk::CompareOp::LESS, STENCIL_COUNT_ZERO + SHOWN_COUNTS, 255));
    }
    let draws = VolumeDraws::new(gpu, scene, options.method == VolumeMethod::ZFail);
    let target = PipelineTarget {
        render_pass: renderer.targets.render_pass,
        colour_attachments: 1,
        samples: SAMPLES,
        lights: 1,
    };
    let frame_layout = renderer.frame_layout;
    let material_layout = draws.meshes.materials.layout();
    let pipelines = PlanPipelines::build(
        gpu,
        &plan,
        false,
        |t| {
            assert_eq!(t, Target::Frame);
            Ok(target)
        },
        |role| Ok(if role == SetRole::Material { material_layout } else { frame_layout }),
    )
    .expect("pipelines");
    let uniforms = FrameUniforms::for_scene(scene, renderer.aspect());
    let clear = scene.background.extend(0.0).to_array();
    renderer
        .render(&uniforms, clear, |rec| record_plan(rec, &plan, &pipelines, true, &|_| true, scene, &draws))
        .expect("frame");
    renderer.read_samples().expect("samples")
}

#[test]
fn the_alpha_counter_equals_the_stencil_count_in_every_sample() {
    let gpu = common::gpu();
    // Stacked casters whose volumes overlap: counts of 2 and more, and edges cutting pixels.
    let scene = builtin_scene("overlap").expect("scene");
    for method in [VolumeMethod::ZPass, VolumeMethod::ZFail] {
        for k in [1u8, 4] {
            // The seed's up-counter (modulate mode): alpha = k x the stencil's count.
            let options = ShadowVolumeOptions { method, increment: k, ..Default::default() };
            let emulated = counts_per_sample(&gpu, &scene, StencilMode::Emulated, options);
            let reference = counts_per_sample(&gpu, &scene, StencilMode::Reference, options);
            let what = format!("{} k = {k}", method.name());
            let (mut shadowed, mut deep, mut cut) = (0, 0, 0);
            for y in 0..emulated.height {
                for x in 0..emulated.width {
                    let counts: Vec<u8> = emulated.pixel(x, y).iter().map(|s| s[3]).collect();
                    let stencil: Vec<u8> = reference.pixel(x, y).iter().map(|s| s[3]).collect();
                    assert_eq!(counts, stencil, "{what}: pixel ({x}, {y}), alpha per sample");
                    assert!(counts.iter().all(|&a| a % k == 0 && a != 255), "{what}: ({x}, {y}) {counts:?}");
                    shadowed += counts.iter().filter(|&&a| a > 0).count();
                    deep += counts.iter().filter(|&&a| a >= 2 * k).count();
                    cut += counts.iter().any(|&a| a != counts[0]) as u32;
                }
            }
            // Not vacuous: shadowed samples, overlapping volumes, and pixels whose samples
            // hold different counts (a volume's edge cuts them).
            assert!(shadowed > 2000 && deep > 100 && cut > 100, "{what}: {shadowed} shadowed, {deep} deep, {cut} cut");
            eprintln!("{what}: {shadowed} shadowed samples, {deep} with a count >= 2, {cut} pixels cut");
        }
    }
    common::assert_no_validation_messages(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Resolved edges and the analytic outline.

/// A frame of `options` at `samples` samples.
fn frame(gpu: &Arc<Gpu>, scene: &Scene, options: &RenderOptions, samples: u32) -> nostencil::TechniqueFrame {
    let options = RenderOptions { samples, ..options.clone() };
    nostencil::render_scene(gpu, scene, &options).expect("frame")
}

/// How far each pixel of `shadowed` is from `unshadowed` toward the full shadow (colour x
/// `factor` / 255 in linear light): 0 lit, 1 shadowed, between them the fraction of its
/// samples in shadow; `None` where the pixel is too dark to tell, or its channels disagree
/// (not a mix of lit and shadowed).
fn shadow_coverage(shadowed: &image::RgbaImage, unshadowed: &image::RgbaImage, factor: u8) -> Vec<Option<f32>> {
    use nostencil::frame::srgb::decode;
    let darkening = 1.0 - factor as f32 / 255.0;
    shadowed
        .chunks_exact(4)
        .zip(unshadowed.chunks_exact(4))
        .map(|(c, u)| {
            let t: Vec<f32> = (0..3)
                .filter(|&i| decode(u[i]) > 0.1)
                .map(|i| (1.0 - decode(c[i]) / decode(u[i])) / darkening)
                .collect();
            let (lo, hi) = t.iter().fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
            (!t.is_empty() && hi - lo < 0.08).then(|| t.iter().sum::<f32>() / t.len() as f32)
        })
        .collect()
}

fn is_between(t: Option<f32>) -> bool {
    t.is_some_and(|t| (0.15..=0.85).contains(&t))
}

/// The box scene, emulated: shadow-volume (subpass and seed) and planar. At 4x the shadow's
/// border resolves to colours between lit and shadowed; the 1x frame has none.
#[test]
fn shadow_edges_resolve_between_lit_and_shadowed_only_at_4x() {
    let gpu = common::gpu();
    let scene = builtin_scene("box").expect("scene");
    let base = RenderOptions { width: 256, height: 192, ..Default::default() };
    let volumes = |normalize| RenderOptions {
        technique: technique("shadow-volume"),
        shadow_volume: ShadowVolumeOptions { normalize, ..Default::default() },
        shadow_mode: ShadowMode::Modulate,
        ..base.clone()
    };
    let planar = RenderOptions { technique: technique("planar"), ..base.clone() };
    let unshadowed_planar =
        RenderOptions { planar: nostencil::PlanarOptions { shadows: false, ..planar.planar }, ..planar.clone() };
    let lit = RenderOptions { technique: technique("lit"), ..base.clone() };
    let cases = [
        ("shadow-volume subpass", volumes(Normalize::Subpass), &lit, ShadowTone::default().darkest()),
        ("shadow-volume seed", volumes(Normalize::Seed), &lit, ShadowTone::default().darkest()),
        ("planar", planar.clone(), &unshadowed_planar, planar.shadow_tone.darkest()),
    ];
    for (what, options, unshadowed, factor) in cases {
        let one = frame(&gpu, &scene, &options, 1).output.image;
        let one_coverage = shadow_coverage(&one, &frame(&gpu, &scene, unshadowed, 1).output.image, factor);
        let four = frame(&gpu, &scene, &options, SAMPLES).output.image;
        let four_coverage = shadow_coverage(&four, &frame(&gpu, &scene, unshadowed, SAMPLES).output.image, factor);
        let shadowed = one_coverage.iter().filter(|t| t.is_some_and(|t| t > 0.9)).count();
        let between_1x = one_coverage.iter().filter(|t| is_between(**t)).count();
        let between: Vec<[u8; 3]> = four
            .chunks_exact(4)
            .zip(&four_coverage)
            .filter(|(_, t)| is_between(**t))
            .map(|(p, _)| [p[0], p[1], p[2]])
            .collect();
        eprintln!("{what}: 1x {shadowed} shadowed, {between_1x} between; 4x {} between", between.len());
        assert!(shadowed > 300, "{what}: {shadowed} shadowed pixels at 1x");
        assert_eq!(between_1x, 0, "{what}: the 1x frame has colours between lit and shadowed");
        assert!(between.len() > 40, "{what}: {} border pixels between lit and shadowed at 4x", between.len());
        // And none of those colours is in the 1x frame at all.
        let colours_1x: std::collections::HashSet<[u8; 3]> = one.chunks_exact(4).map(|p| [p[0], p[1], p[2]]).collect();
        let shared = between.iter().filter(|c| colours_1x.contains(*c)).count();
        assert_eq!(shared, 0, "{what}: {shared} border colours of the 4x frame also appear at 1x");
    }
    common::assert_no_validation_messages(&gpu);
}

/// As tests/inside/shadow_volume.rs's 1x check, at 4x: the ground pixels shadowed to at least half
/// coverage (`shadow_coverage` >= 0.5) against those whose centre lies inside the casters'
/// projected outline, computed on the CPU (every casting triangle projected along the light
/// onto the ground). Pixels where the 4x lit frame shows a caster (its edges included) are
/// left out.
#[test]
fn the_box_shadow_at_4x_thresholded_at_half_coverage_is_its_projected_outline() {
    const BIG: (u32, u32) = (256, 192);
    let (width, height) = BIG;
    let gpu = common::gpu();
    let scene = builtin_scene("box").expect("scene");
    let triangles = common::caster_triangles_on_ground(&scene);
    let base = RenderOptions { width, height, ..Default::default() };
    let lit = RenderOptions { technique: technique("lit"), ..base.clone() };
    let unshadowed = frame(&gpu, &scene, &lit, SAMPLES).output.image;
    let mut without = scene.clone();
    without.objects.retain(|o| !o.casts_shadow);
    let background = frame(&gpu, &without, &lit, SAMPLES).output.image;
    let caster_pixels = common::differing_pixels(&unshadowed, &background);
    for &normalize in Normalize::ALL {
        // The seed's frame: a shadowed pixel is the lit one times D (`shadow_coverage`).
        let options = ShadowVolumeOptions { normalize, ..Default::default() };
        let volumes = RenderOptions {
            technique: technique("shadow-volume"),
            shadow_volume: options,
            shadow_mode: ShadowMode::Modulate,
            ..base.clone()
        };
        let shadowed = frame(&gpu, &scene, &volumes, SAMPLES).output.image;
        let coverage = shadow_coverage(&shadowed, &unshadowed, volumes.shadow_tone.darkest());
        let dark = |i: usize| coverage[i].is_some_and(|t| t >= 0.5);
        let (both, either) = common::outline_overlap(&scene.camera, BIG, &triangles, &caster_pixels, dark);
        let partial = caster_pixels.iter().zip(&coverage).filter(|(&skip, &c)| !skip && is_between(c)).count();
        let iou = both as f64 / either as f64;
        eprintln!("{}: IoU {iou:.4} over {either} pixels, {partial} partly covered", normalize.name());
        assert!(either > 200, "{}: the shadow is too small to judge ({either} pixels)", normalize.name());
        // Not vacuous: the edges are anti-aliased (the threshold decides them).
        assert!(partial > 20, "{}: {partial} partly covered pixels", normalize.name());
        assert!(iou >= 0.99, "{}: intersection over union {iou:.4}", normalize.name());
    }
    common::assert_no_validation_messages(&gpu);
}

/// The additive loop at 4x with k = 4 (tests/inside/shadow_volume.rs runs it at 1x): emulated
/// equals Ogre's per-light stencil loop on `overlap` and `lights` (the deepest counts and the
/// most lights), z-fail and the scene's choice, all three normalisations. Per sample: the mask,
/// the depth-equal shading and the reset all blend per sample, and the reference's stencil tests
/// per sample. At k = 1 every built-in scene's additive loop is drawn at 4x, in both counting
/// methods and each normalisation the additive loop has (the max path draws the seed path's
/// frame there), by tests/inside/plan.rs's
/// `multisampled_frames_without_a_stencil_equal_their_stencil_reference`; this test ran it
/// again on every scene (19 s) and keeps only what k changes, the blend arithmetic.
#[test]
fn additive_emulated_equals_reference_at_4x_with_k_4() {
    let gpu = common::gpu();
    let base = RenderOptions { width: 96, height: 72, technique: technique("shadow-volume"), ..Default::default() };
    for name in ["overlap", "lights"] {
        let scene = builtin_scene(name).expect("scene");
        for method in [VolumeMethod::Auto, VolumeMethod::ZFail] {
            let with = |stencil, increment, normalize| RenderOptions {
                stencil,
                shadow_volume: ShadowVolumeOptions { method, increment, normalize, ..Default::default() },
                ..base.clone()
            };
            let reference = frame(&gpu, &scene, &with(StencilMode::Reference, 1, Normalize::Seed), SAMPLES);
            for &normalize in Normalize::ALL {
                let emulated = frame(&gpu, &scene, &with(StencilMode::Emulated, 4, normalize), SAMPLES);
                let differing = emulated
                    .output
                    .image
                    .chunks_exact(4)
                    .zip(reference.output.image.chunks_exact(4))
                    .filter(|(a, b)| a[..3] != b[..3])
                    .count();
                assert_eq!(differing, 0, "{name} {method:?} k=4 {}: {differing} pixels differ", normalize.name());
            }
        }
    }
    common::assert_no_validation_messages(&gpu);
}

// ---------------------------------------------------------------------------------------------
// Saturation, per sample.

/// Ground, and `boxes` thin boxes stacked under a light straight down: ground pixels under the
/// stack sit inside up to `boxes` volumes (as tests/inside/shadow_volume.rs's saturation scene).
fn stack_scene(boxes: usize) -> Scene {
    let mut scene = builtin_scene("box").expect("scene");
    scene.objects.retain(|o| o.name == "ground");
    scene.set_light(nostencil::Light::Directional { direction: glam::Vec3::NEG_Y });
    let cube = scene.add_mesh("thin box", nostencil::mesh::shapes::cube(1.0));
    for i in 0..boxes {
        let transform = glam::Mat4::from_scale_rotation_translation(
            glam::Vec3::new(1.5, 0.05, 1.5),
            glam::Quat::IDENTITY,
            glam::Vec3::new(0.0, 0.5 + 0.1 * i as f32, 0.0),
        );
        scene.add_object(&format!("layer {i}"), cube, transform, glam::Vec3::ONE, true);
    }
    scene
}

/// docs/design/saturation.md at 4x: 40 stacked volumes at k = 8 (the counter holds 31). The subpass
/// apply's atomic count, the probe's samples passed and the samples whose alpha the per-sample
/// read-back finds at its clamp are one number, a count of samples: about 4 times the 1x
/// frame's count of pixels. (It found the apply counting every saturated sample 4 times under
/// lavapipe, which shades this pass once per sample: the shader now counts only the samples
/// its invocation covers.)
#[test]
fn saturation_is_counted_per_sample_at_4x() {
    let gpu = common::gpu();
    let scene = stack_scene(40);
    let (width, height) = (128, 96);
    let options = |samples, saturation_probe| RenderOptions {
        width,
        height,
        samples,
        keep_samples: samples > 1,
        technique: technique("shadow-volume"),
        // The seed's up-counter, whose clamp the probe and the read-back find at alpha 255.
        shadow_volume: ShadowVolumeOptions {
            increment: 8,
            normalize: Normalize::Subpass,
            saturation_probe,
            ..Default::default()
        },
        shadow_mode: nostencil::ShadowMode::Modulate,
        ..Default::default()
    };
    let run = |options: RenderOptions| {
        let mut renderer = options.technique.build(&gpu, &scene, &options).expect("renderer");
        let frame = renderer.frame_with(&scene).expect("frame");
        let stats = frame.stats::<nostencil::stats::ShadowVolumeStats>().expect("statistics").clone();
        let samples = (options.samples > 1).then(|| renderer.renderer_mut().read_samples().expect("samples"));
        (stats, samples)
    };
    let (one, _) = run(options(1, false));
    let pixels = one.saturated_samples.expect("the subpass apply counts at 1x");
    let (four, kept) = run(options(SAMPLES, true));
    let counted = four.saturated_samples.expect("the subpass apply counts at 4x");
    // The samples at the clamp, read back (the apply changes colour only, alpha keeps the count).
    let kept = kept.expect("samples kept");
    let clamped = kept.bytes.chunks_exact(4).filter(|s| s[3] == 255).count() as u64;
    assert_eq!(counted, clamped, "the atomic count is not the number of clamped samples");
    assert_eq!(four.probe_saturated_samples, Some(counted), "apply and probe disagree at 4x");
    // Samples, not pixels: every pixel inside the stack's shadow has its 4 samples saturated.
    let clamped_pixels = (0..height)
        .flat_map(|y| (0..width).map(move |x| (x, y)))
        .filter(|&(x, y)| kept.pixel(x, y).iter().any(|s| s[3] == 255))
        .count() as u64;
    eprintln!("1x: {pixels} saturated pixels; 4x: {counted} saturated samples in {clamped_pixels} pixels");
    assert!(pixels > 50, "{pixels} saturated pixels at 1x");
    assert!(counted > clamped_pixels, "{counted} samples in {clamped_pixels} pixels");
    // About 4 samples where 1x counts one pixel (not exactly: the samples are not at the
    // pixel's centre, and where coincident walls of 40 volumes meet them is rasterisation's
    // call). A count of pixels would be near 1.
    let ratio = counted as f64 / pixels as f64;
    assert!((3.0..=5.0).contains(&ratio), "4x counts {counted} samples where 1x counts {pixels} pixels");
    common::assert_no_validation_messages(&gpu);
}
