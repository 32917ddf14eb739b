//! The shadow-volume renderer: casters prepared once, each volume built again only when its
//! light, reach or caster moved (else the buffers of the frames before are drawn again), written
//! into buffers kept from frame to frame (made again only when a volume outgrows them), drawn by
//! the plan of `recipes`. What a frame reports is in `stats`.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec4};

use super::bounds;
use super::casters::{build_volume_into, choose_zfail, light_in_object_space, prepare_casters, Caster, VolumeScratch};
use super::culling::{self, Culling, KeptCulling};
use super::doubled::{Doubled, DoubledVertices};
use super::gpu_extrusion::{ExtrudedVolume, ShadowMeshes, VolumePush};
use super::near_caps::{DrawnBy, NearCapSplit};
use super::recipes::SATURATION_PROBE;
use super::recipes::{is_extruded, VolumeDraw, VolumeKinds, VolumeSet};
pub use super::stats::{CasterReport, LightReport, ShadowVolumeStats};
use super::stats::{
    MEASURED_BY_APPLY, MEASURED_BY_MASK, MEASURED_BY_PROBE, NOT_COUNTED_REFERENCE, NOT_MEASURED, NOT_MEASURED_ADDITIVE,
    NOT_MEASURED_NO_ATOMICS,
};
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::{Buffer, ReusedBuffer};
use crate::gpu::Gpu;
use crate::mesh::caster::CastPath;
use crate::mesh::{Reach, VolumeGeometry};
use crate::pipeline::recipes::STENCIL_COUNT_ZERO;
use crate::render::jobs::{self, PerWorker};
use crate::render::per_slot::slot_copy;
use crate::render::passes::Passes;
use crate::render::plan::{Draws, PlannedPass, Scissor};
use crate::render::Pipeline;
use crate::render::{BoundDraw, FrameOutput, FrameRecorder, GpuScene, Renderer};
use crate::scene::model::AlphaMode;
use crate::scene::{Light, Scene, SceneLight};
use crate::technique::alpha_counter;
use crate::technique::frame_renderer::BuildContext;
use crate::technique::interface::{FrameStats, RenderOptions};
use crate::technique::options::{Normalize, ShadowMode, ShadowVolumeOptions, VolumeExtrusion, VolumeMethod};
use crate::technique::shadow_tone::ShadowTone;
use crate::technique::unit::Prepared;

/// One caster's volume for this frame.
struct GpuVolume {
    /// Its caster's index among the frame's casters: which of its light's buffers hold it.
    caster: usize,
    form: VolumeForm,
    /// Where it can shade: its walls are rasterised only there.
    scissor: vk::Rect2D,
}

impl GpuVolume {
    /// Its near caps drawn by one counting pipeline (`near_caps`): those before the
    /// front-keeping pipeline's run, and those after the back-keeping one's.
    fn near_caps_one_pipeline(&self) -> u64 {
        let VolumeForm::Indexed { ranges, .. } = &self.form else { return 0 };
        let run = |by: DrawnBy| ranges.iter().find(|r| r.drawn_by == by);
        match (run(DrawnBy::FrontKeeping), run(DrawnBy::BackKeeping), run(DrawnBy::Unculled)) {
            (Some(front), Some(back), Some(whole)) => u64::from(front.first + whole.count - back.count) / 3,
            _ => 0,
        }
    }
}

/// How a volume reaches the GPU.
enum VolumeForm {
    /// Its indices chosen on the CPU into its light's and caster's index buffer (Doom 3 BFG),
    /// over doubled vertices (the mesh's, or a skinned caster's posed copy in the same
    /// buffers) that the vertex shader extrudes as `push` says: what to draw, and how many
    /// counts each of its fragments adds.
    Indexed { ranges: Vec<IndexRange>, push: VolumePush },
    /// Extruded in the vertex shader from its mesh's tables.
    Extruded(ExtrudedVolume),
}

/// The buffers one caster's volume for one light is written into, frame after frame: made once,
/// and again only when a volume outgrows them.
struct VolumeBuffers {
    vertices: ReusedBuffer,
    indices: ReusedBuffer,
    /// What they hold.
    built: Option<BuiltVolume>,
}

impl VolumeBuffers {
    fn new() -> Self {
        VolumeBuffers {
            vertices: ReusedBuffer::new("shadow volume vertices", vk::BufferUsageFlags::VERTEX_BUFFER),
            indices: ReusedBuffer::new("shadow volume indices", vk::BufferUsageFlags::INDEX_BUFFER),
            built: None,
        }
    }
}

/// Indices `first..first + count` of a volume, whose every fragment adds `times` counts: drawn
/// once with `times` k (the alpha counter), or `times` times over (the stencil's +1 ops, for
/// which a volume has one range of every copy).
#[derive(Debug, Clone, Copy)]
struct IndexRange {
    first: u32,
    count: u32,
    times: u32,
    /// Which pipelines draw it (a volume whose near caps are split has one range per kind).
    drawn_by: DrawnBy,
}

/// What is worked out from the scene before the frame is planned: the casters, whose volumes
/// decide whether `auto` counts z-fail for this camera.
///
/// `Default` (no casters, z-pass) only because every unit's `Setup` has one, for units whose
/// `setup` is the trait's; this unit always works its setup out in `setup`.
#[derive(Default)]
pub struct VolumeSetup {
    casters: Vec<Caster>,
    warnings: Vec<String>,
    zfail: bool,
    /// The options as asked (`auto` still `auto`).
    requested: ShadowVolumeOptions,
}

/// Prepares the casters and resolves the counting method (and whether the subpass apply can
/// count saturation: only where the device has fragment atomics, and the caller did not turn
/// them off, as a port for a device without them would). The options were checked by
/// `unit::build_unit`, k among them.
pub fn setup(gpu: &Gpu, scene: &Scene, options: &RenderOptions) -> Result<Prepared<VolumeSetup>> {
    let (casters, warnings) = prepare_casters(scene);
    let aspect = options.width as f32 / options.height as f32;
    let zfail = choose_zfail(&options.shadow_volume, scene, &casters, aspect);
    let method = if zfail { VolumeMethod::ZFail } else { VolumeMethod::ZPass };
    let fragment_atomics =
        options.shadow_volume.fragment_atomics && gpu.device.info.features.fragment_stores_and_atomics;
    let resolved = RenderOptions {
        shadow_volume: ShadowVolumeOptions { method, fragment_atomics, ..options.shadow_volume },
        ..options.clone()
    };
    let requested = options.shadow_volume;
    Ok(Prepared { options: resolved, setup: VolumeSetup { casters, warnings, zfail, requested } })
}

/// The technique's part of the renderer, planned with the resolved options.
pub fn make(ctx: BuildContext<'_, VolumeKinds>, scene: &Scene, setup: VolumeSetup) -> Result<ShadowVolumePasses> {
    let VolumeSetup { casters, mut warnings, zfail, requested } = setup;
    // `setup` resolves the counting method only: the mode is the one asked for.
    let mode = ctx.options.shadow_mode;
    if mode == ShadowMode::Additive && requested.saturation_probe {
        warnings.push(
            "--saturation-probe reads the modulate mode's up-counter and is not drawn in additive mode (the default); \
             there --normalize subpass counts saturated samples"
                .into(),
        );
    }
    if mode == ShadowMode::Additive && ctx.options.shadow_tone != ShadowTone::default() {
        warnings.push(
            "--shadow-factor and --shadow-colour shape the modulate mode's shadow; in additive mode (the default) a \
             shadow leaves its light out and the ambient term in (add --shadow-mode modulate)"
                .into(),
        );
    }
    let options = ctx.options;
    let k = alpha_counter::check_increment(options.shadow_volume.increment)?;
    let fragment_atomics = options.shadow_volume.fragment_atomics;
    let counting = ctx.options.stencil == StencilMode::Emulated
        && ctx.options.shadow_volume.normalize == Normalize::Subpass
        && fragment_atomics;
    let saturation_counter = if counting {
        Some(Buffer::with_data(ctx.gpu, "saturated sample count", &[0u32], vk::BufferUsageFlags::STORAGE_BUFFER)?)
    } else {
        None
    };
    // The colour the subpass normalisation reads back: the renderer's own image. A frame drawn
    // into swapchain images has none at one sample, and then its plan reads no colour
    // (`FrameTargets::presenting`): the set is not made.
    let counter_input = match (ctx.options.stencil, ctx.renderer.targets.drawn_colour()) {
        (StencilMode::Emulated, Some(drawn_colour)) => {
            let mut bindings = vec![Binding::InputAttachment {
                view: drawn_colour.view,
                layout: vk::ImageLayout::GENERAL,
            }];
            if let Some(buffer) = &saturation_counter {
                bindings.push(Binding::FragmentStorageBuffer { buffer: buffer.raw, range: buffer.size });
            }
            Some(DescriptorSet::new(ctx.gpu, &bindings)?)
        }
        _ => None,
    };
    let additive = mode == ShadowMode::Additive;
    let saturation_measured_by = match ctx.options.stencil {
        StencilMode::Reference => NOT_COUNTED_REFERENCE,
        StencilMode::Emulated if additive && counting => MEASURED_BY_MASK,
        StencilMode::Emulated if additive => NOT_MEASURED_ADDITIVE,
        StencilMode::Emulated if counting => MEASURED_BY_APPLY,
        StencilMode::Emulated if ctx.options.shadow_volume.saturation_probe => MEASURED_BY_PROBE,
        StencilMode::Emulated if ctx.options.shadow_volume.normalize == Normalize::Subpass => NOT_MEASURED_NO_ATOMICS,
        StencilMode::Emulated => NOT_MEASURED,
    };
    let capacity = alpha_counter::capacity(k);
    let primary = scene.primary_light_index().unwrap_or(0);
    let shadowed: Vec<bool> = match mode {
        ShadowMode::Additive => scene.lights.iter().map(|l| l.casts_shadow).collect(),
        ShadowMode::Modulate => (0..scene.lights.len()).map(|i| i == primary).collect(),
    };
    let reports = casters.iter().map(|c| CasterReport::new(scene, c, capacity)).collect();
    let meshes = GpuScene::upload_for(ctx.gpu, scene, ctx.options.skinning)?;
    let doubled = DoubledVertices::upload(ctx.gpu, scene, &casters, meshes.joint_palettes())?;
    let shadow_meshes = match options.shadow_volume.extrusion {
        VolumeExtrusion::Shader => Some(ShadowMeshes::upload(ctx.gpu, scene, &casters, &mut warnings)?),
        VolumeExtrusion::Indices => None,
    };
    Ok(ShadowVolumePasses {
        gpu: ctx.gpu.clone(),
        requested,
        mode,
        casters,
        warnings,
        meshes,
        shadow_meshes,
        doubled,
        counter_input,
        saturation_counter,
        stencil: ctx.options.stencil,
        volumes: Vec::new(),
        buffers: Vec::new(),
        scratch: PerWorker::default(),
        covers: Vec::new(),
        light_rects: Vec::new(),
        kept_culling: Vec::new(),
        primary,
        shadowed,
        stats: ShadowVolumeStats {
            zfail,
            seed_iterations: alpha_counter::seed_iterations(k, options.shadow_tone.darkest())?,
            capacity,
            saturated_samples: None,
            saturation_measured_by,
            probe_saturated_samples: None,
            increment: k,
            casters: reports,
            mode: mode.name(),
            lights: Vec::new(),
            culling_cpu_ms: 0.0,
        },
    })
}

pub struct ShadowVolumePasses {
    gpu: Arc<Gpu>,
    /// The options as asked (`auto` still `auto`: the viewer asks whether the camera moved
    /// into or out of a volume).
    requested: ShadowVolumeOptions,
    /// The frame's loop: additive or the seeds' modulated frame.
    mode: ShadowMode,
    casters: Vec<Caster>,
    /// Casting objects that cast nothing, and why.
    warnings: Vec<String>,
    meshes: GpuScene,
    /// The casters' tables, with `--volume-extrusion shader`.
    shadow_meshes: Option<ShadowMeshes>,
    /// The rigid casters' doubled vertices, which every volume with CPU-chosen indices draws.
    doubled: DoubledVertices,
    /// The colour target as an input attachment (emulated: the probe and `subpass`), and the
    /// saturation counter at binding 1 when the subpass apply counts.
    counter_input: Option<DescriptorSet>,
    /// One u32 the subpass apply adds each pixel's saturated samples to (declared after the set that
    /// names it, so that it is dropped after it).
    saturation_counter: Option<Buffer>,
    /// This frame's volumes per light (those that can shade something on screen; none for a
    /// light the plan does not shadow).
    volumes: Vec<Vec<GpuVolume>>,
    /// Per frame slot, per light, per caster: the buffers its volume is written into, kept
    /// from frame to frame (a slot's are read by the frame in flight in it).
    buffers: Vec<Vec<Vec<VolumeBuffers>>>,
    /// Where the jobs that build volumes build them before writing them into their buffers,
    /// one per worker.
    scratch: PerWorker<VolumeScratch>,
    /// Per light: where its full-screen passes draw (the union of its volumes' scissors).
    covers: Vec<Scissor>,
    /// Per light: its light scissor (Doom 3's), where its shading pass draws.
    light_rects: Vec<Scissor>,
    /// Per light: the culling last decided, kept while neither it nor a caster moves.
    kept_culling: Vec<Option<KeptCulling>>,
    /// The light the modulate mode shadows.
    primary: usize,
    /// Which lights get volumes: the shadowing ones (additive), the primary one (modulate).
    shadowed: Vec<bool>,
    stats: ShadowVolumeStats,
    /// Which counter draws the volumes (repeated walls: copies for the stencil).
    stencil: StencilMode,
}

impl Passes<VolumeKinds> for ShadowVolumePasses {
    fn set(&self, set: VolumeSet) -> Option<&DescriptorSet> {
        match set {
            VolumeSet::CounterInput => self.counter_input.as_ref(),
            VolumeSet::ShadowMeshes => self.shadow_meshes.as_ref().map(ShadowMeshes::set),
        }
    }

    fn meshes(&self) -> Option<&GpuScene> {
        Some(&self.meshes)
    }

    /// A light's shading pass draws in its light scissor; full-screen passes in the cover of
    /// its volumes (the modulate apply: the primary light's).
    fn scissor(&self, pass: &PlannedPass<VolumeKinds>) -> Scissor {
        let light = pass.light.map_or(self.primary, usize::from);
        let per_light = if matches!(pass.draws, Draws::Objects { .. }) { &self.light_rects } else { &self.covers };
        per_light.get(light).cloned().unwrap_or(Scissor::Frame)
    }

    /// Every volume with the pass's first pipeline (bound by the recorder), then again with each
    /// further one: the alpha counter's decrements come after all its increments.
    fn draw(
        &self,
        rec: &mut FrameRecorder,
        _scene: &Scene,
        draw: VolumeDraw,
        _pass: &PlannedPass<VolumeKinds>,
        pipelines: &[&Pipeline],
    ) -> Result<()> {
        let VolumeDraw::Volumes { alpha, light, clear_stencil } = draw;
        let light = usize::from(light);
        if clear_stencil {
            // Ogre's and Doom 3's per-light clear, in the light's scissor grown by the pixel a
            // multisampled scissored draw may reach past it (docs/design/msaa.md).
            let rect = match self.light_rects.get(light) {
                Some(Scissor::Rects(rects)) => rects.first().map(|r| bounds::grown(*r, 1, rec.extent)),
                _ => Some(vk::Rect2D { offset: vk::Offset2D::default(), extent: rec.extent }),
            };
            if let Some(rect) = rect {
                rec.clear_stencil_in(STENCIL_COUNT_ZERO, rect);
            }
        }
        let volumes = self.volumes.get(light).map_or(&[][..], Vec::as_slice);
        let buffers = self.buffers.get(rec.slot()).and_then(|lights| lights.get(light)).map_or(&[][..], Vec::as_slice);
        for (index, pipeline) in pipelines.iter().enumerate() {
            if index > 0 {
                rec.bind(pipeline);
            }
            // Each pipeline draws the volumes of its form: the CPU form's pipeline those built
            // on the CPU, its GPU-extruded twin (next in the pass) the others.
            if is_extruded(&pipeline.desc) {
                let Some(shadow_meshes) = &self.shadow_meshes else { continue };
                shadow_meshes.bind(rec, pipeline);
                for volume in volumes {
                    if let VolumeForm::Extruded(extruded) = &volume.form {
                        rec.set_scissor(volume.scissor);
                        shadow_meshes.draw(rec, pipeline, extruded, alpha);
                    }
                }
                continue;
            }
            // Casters skinned on the GPU last, with the pipeline's skinned twin. A volume
            // pushes once for all its ranges (each passes its multiplicity as its first
            // instance), and sets its scissor only where it changed (the recorder binds only
            // what changed): lavapipe allocates every command it records.
            for skinned_pass in [false, true] {
                let pipeline: &Pipeline = pipeline;
                let mut bound = pipeline;
                let mut scissor = None;
                for volume in volumes {
                    let VolumeForm::Indexed { ranges, push } = &volume.form else { continue };
                    let Some(slot) = buffers.get(volume.caster) else { continue };
                    let vertices = match self.doubled.of_caster(volume.caster) {
                        Some(Doubled::Rigid { vertices, first_vertex }) if !skinned_pass => {
                            Some((vertices, first_vertex))
                        }
                        Some(Doubled::Skinned(bind_pose)) if skinned_pass => Some((bind_pose, 0)),
                        None if !skinned_pass => slot.vertices.filled().map(|(buffer, _)| (buffer, 0)),
                        _ => None,
                    };
                    let Some(((vertices, vertex_offset), (indices, _))) = vertices.zip(slot.indices.filled()) else {
                        continue;
                    };
                    if skinned_pass && std::ptr::eq(bound, pipeline) {
                        bound = pipeline.skinned().ok_or_else(|| {
                            Error::Internal(format!("volume pipeline '{}' has no skinned twin", pipeline.desc.name))
                        })?;
                        rec.bind(bound);
                    }
                    if scissor != Some(volume.scissor) {
                        rec.set_scissor(volume.scissor);
                        scissor = Some(volume.scissor);
                    }
                    rec.bind_indexed(vertices, indices);
                    rec.push(bound, &VolumePush { colour: Vec4::new(0.0, 0.0, 0.0, alpha), ..*push });
                    let cull = bound.desc.fixed.raster.cull;
                    for range in ranges.iter().filter(|range| range.drawn_by.draws_with(cull)) {
                        rec.draw_bound(BoundDraw {
                            first_index: range.first,
                            index_count: range.count,
                            vertex_offset,
                            first_instance: range.times,
                        });
                    }
                }
            }
        }
        Ok(())
    }

    fn prepare(&mut self, renderer: &Renderer, scene: &Scene) -> Result<()> {
        let slot = renderer.slot();
        self.meshes.follow_pose(&self.gpu, scene, slot)?;
        slot_copy(&mut self.buffers, slot, || Ok(Vec::new()))?;
        let extent = renderer.extent();
        let boxes = bounds::object_boxes_in_jobs(&self.gpu, scene);
        let receivers = bounds::receivers_box(&boxes);
        (self.volumes, self.covers, self.light_rects, self.stats.lights) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        self.stats.culling_cpu_ms = 0.0;
        for (index, light) in scene.lights.iter().enumerate() {
            let light_rect = if self.requested.clip_volumes {
                bounds::light_scissor(light, receivers, &scene.camera, extent)
            } else {
                Scissor::Frame
            };
            let shadows = self.shadowed.get(index).copied().unwrap_or(false);
            if self.kept_culling.len() <= index {
                self.kept_culling.resize_with(index + 1, || None);
            }
            let (culled, culling_reused) = if shadows && self.requested.cull_casters {
                culling::hidden_casters_kept(&mut self.kept_culling[index], scene, &self.casters, light, &boxes)
            } else {
                (Culling::none(self.casters.len()), false)
            };
            self.stats.culling_cpu_ms += culled.cpu_ms;
            let (mut reused, mut extruded) = (0, 0);
            let volumes = if shadows {
                let lit = LitBy { light, rect: &light_rect, culled: &culled, boxes: &boxes };
                let counting = Counting {
                    zfail: self.stats.zfail,
                    stencil: self.stencil,
                    split_near_caps: self.requested.split_near_caps,
                };
                let lights = &mut self.buffers[slot];
                if lights.len() <= index {
                    lights.resize_with(index + 1, Vec::new);
                }
                let buffers = &mut lights[index];
                if buffers.len() < self.casters.len() {
                    buffers.resize_with(self.casters.len(), VolumeBuffers::new);
                }
                let uploads = Uploads {
                    gpu: &self.gpu,
                    buffers,
                    reused: &mut reused,
                    extruded: &mut extruded,
                    scratch: &self.scratch,
                    shadow_meshes: self.shadow_meshes.as_ref(),
                    doubled: &self.doubled,
                };
                upload_volumes(uploads, scene, &self.casters, counting, self.requested, extent, lit)?
            } else {
                Vec::new()
            };
            self.covers.push(if self.requested.clip_volumes {
                let rects: Vec<vk::Rect2D> = volumes.iter().map(|v| v.scissor).collect();
                Scissor::Rects(bounds::disjoint_cover(&rects))
            } else {
                Scissor::Frame
            });
            self.stats.lights.push(LightReport {
                name: light.name.clone(),
                shadows,
                volumes: volumes.len(),
                reused,
                extruded,
                culled: culled.count(),
                culling_reused,
                near_caps_one_pipeline: volumes.iter().map(GpuVolume::near_caps_one_pipeline).sum(),
                volume_fill: None,
                volume_samples_passed: 0.0,
            });
            self.volumes.push(volumes);
            self.light_rects.push(light_rect);
        }
        // The previous frame has finished (frames wait for their fence): the count restarts.
        if let Some(counter) = &mut self.saturation_counter {
            counter.write(0, &[0u32])?;
        }
        Ok(())
    }

    /// The counter's start: a count of 0 is alpha 0 counting up (modulate), 1 counting down
    /// (additive).
    fn clear_alpha(&self) -> f32 {
        match self.mode {
            ShadowMode::Modulate => 0.0,
            ShadowMode::Additive => 1.0,
        }
    }

    fn clear_stencil(&self) -> u32 {
        STENCIL_COUNT_ZERO
    }

    fn stats(&mut self, output: &FrameOutput, _scene: &Scene) -> Box<dyn FrameStats> {
        let mut stats = self.stats.clone();
        let pixels = f64::from(output.counters.width) * f64::from(output.counters.height);
        let samples = pixels * f64::from(output.counters.samples.max(1));
        for (index, light) in stats.lights.iter_mut().enumerate() {
            // Additive passes are named after their light; the modulate frame has one set,
            // the primary light's.
            let prefix = match self.mode {
                ShadowMode::Additive => format!("{}: volumes", light.name),
                ShadowMode::Modulate if index == self.primary => "volumes".to_owned(),
                ShadowMode::Modulate => continue,
            };
            let passes: Vec<_> = output.counters.passes.iter().filter(|p| p.name.starts_with(&prefix)).collect();
            light.volume_fill =
                passes.iter().map(|p| p.fragment_invocations).sum::<Option<u64>>().map(|f| f as f64 / pixels);
            light.volume_samples_passed = passes.iter().map(|p| p.samples_passed).sum::<u64>() as f64 / samples;
        }
        stats.probe_saturated_samples = output.counters.pass(SATURATION_PROBE).map(|p| p.samples_passed);
        stats.saturated_samples = match &self.saturation_counter {
            Some(counter) => counter
                .read()
                .ok()
                .and_then(|bytes| bytes.get(..4))
                .map(|b| u64::from(u32::from_ne_bytes([b[0], b[1], b[2], b[3]]))),
            None => stats.probe_saturated_samples,
        };
        Box::new(stats)
    }

    /// Everything but the saturation counter, read back after its frame, is written per slot.
    fn writes_per_slot(&self) -> bool {
        self.saturation_counter.is_none()
    }

    fn stale_for(&self, renderer: &Renderer, scene: &Scene) -> bool {
        choose_zfail(&self.requested, scene, &self.casters, renderer.aspect()) != self.stats.zfail
    }

    fn warnings(&self) -> &[String] {
        &self.warnings
    }
}

/// How the volumes are counted: the method, and by which counter (the stencil draws repeated
/// walls as copies, the alpha counter once with their multiplicity).
#[derive(Debug, Clone, Copy)]
struct Counting {
    zfail: bool,
    stencil: StencilMode,
    /// Asked for (`--whole-near-caps` not given); done only where `near_caps` says it is exact.
    split_near_caps: bool,
}

/// The light a frame's volumes are built for, its light scissor, and the casters it culls.
struct LitBy<'a> {
    light: &'a SceneLight,
    rect: &'a Scissor,
    culled: &'a Culling,
    /// Every object's posed world box, computed once a frame ([`bounds::object_boxes`]).
    boxes: &'a [Option<bounds::Aabb>],
}

/// Where a light's volumes go: each caster's buffers, rewritten in place.
struct Uploads<'a> {
    gpu: &'a Arc<Gpu>,
    buffers: &'a mut [VolumeBuffers],
    /// Counts the volumes whose buffers already held them.
    reused: &'a mut usize,
    /// Counts the volumes extruded on the GPU.
    extruded: &'a mut usize,
    /// What the jobs that build volumes write into, one per worker.
    scratch: &'a PerWorker<VolumeScratch>,
    /// The casters' tables, where volumes are extruded on the GPU.
    shadow_meshes: Option<&'a ShadowMeshes>,
    /// The doubled vertices uploaded at build (which skinned casters are skinned on the GPU).
    doubled: &'a DoubledVertices,
}

/// How a caster's volume was had this frame, for the light's report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    Built,
    /// Its buffers already held it.
    Reused,
    ExtrudedOnGpu,
}

fn upload_volumes(
    uploads: Uploads,
    scene: &Scene,
    casters: &[Caster],
    counting: Counting,
    options: ShadowVolumeOptions,
    extent: vk::Extent2D,
    lit: LitBy,
) -> Result<Vec<GpuVolume>> {
    // Unclipped: no receivers' box, so every volume reaches infinity over the whole frame.
    let boxes = if options.clip_volumes { lit.boxes } else { &[] };
    // Volumes stay a pixel inside the light's scissor, where its shading pass resets the
    // counter even where a multisampled scissored draw reaches a pixel past its edge.
    let inner = match lit.rect {
        Scissor::Frame => None,
        Scissor::Rects(rects) => match rects.first() {
            Some(rect) => Some(bounds::shrunk(*rect, 1)),
            None => return Ok(Vec::new()),
        },
    };
    let frame = FrameOfVolumes {
        scene,
        counting,
        extent,
        light: lit.light,
        geometry: lit.light.geometry(),
        boxes,
        receivers: bounds::receivers_box(boxes),
        inner,
        gpu: uploads.gpu,
        scratch: uploads.scratch,
        shadow_meshes: uploads.shadow_meshes,
        doubled: uploads.doubled,
    };
    // One job per caster, each with its own buffers: where its volume goes this frame, and
    // the volume itself where its light, reach or pose moved (Doom 3 BFG's shadow jobs).
    let jobs: Vec<(usize, &mut VolumeBuffers)> = uploads
        .buffers
        .iter_mut()
        .enumerate()
        .take(casters.len())
        .filter(|(index, _)| {
            let measured_alone = options.only_caster.map_or(true, |only| only as usize == *index);
            !lit.culled.is_hidden(*index) && measured_alone
        })
        .collect();
    let done = jobs::run(uploads.gpu, jobs, |(index, slot)| frame.volume_of(index, &casters[index], slot));
    let mut volumes = Vec::with_capacity(done.len());
    for result in done {
        let Some((volume, source)) = result? else { continue };
        match source {
            Source::Reused => *uploads.reused += 1,
            Source::ExtrudedOnGpu => *uploads.extruded += 1,
            Source::Built => {}
        }
        volumes.extend(volume);
    }
    Ok(volumes)
}

/// What every caster's volume job reads: the frame, the light, and where volumes are built.
struct FrameOfVolumes<'a> {
    scene: &'a Scene,
    counting: Counting,
    extent: vk::Extent2D,
    light: &'a SceneLight,
    geometry: Light,
    /// The objects' boxes (none: volumes unclipped), the receivers' box, and the light's
    /// scissor shrunk by a pixel.
    boxes: &'a [Option<bounds::Aabb>],
    receivers: Option<bounds::Aabb>,
    inner: Option<Option<vk::Rect2D>>,
    gpu: &'a Arc<Gpu>,
    scratch: &'a PerWorker<VolumeScratch>,
    shadow_meshes: Option<&'a ShadowMeshes>,
    doubled: &'a DoubledVertices,
}

impl FrameOfVolumes<'_> {
    /// Caster `index`'s volume this frame, built into `slot` where it moved, and how it was
    /// had (no volume: it casts nothing); `None` where it is not drawn at all this frame.
    fn volume_of(
        &self,
        index: usize,
        caster: &Caster,
        slot: &mut VolumeBuffers,
    ) -> Result<Option<(Option<GpuVolume>, Source)>> {
        let (scene, counting) = (self.scene, self.counting);
        let object = &scene.objects[caster.object];
        // Clipped: the volume ends past the receivers and is scissored to where it can shade;
        // a caster whose volume misses every receiver, or lies off screen, or out of the
        // light's reach, is not drawn.
        let (reach, scissor) = match (self.receivers, self.boxes.get(caster.object).copied().flatten()) {
            (Some(receivers), Some(caster_box)) => {
                if !self.light.reaches_box(caster_box.lo, caster_box.hi) {
                    return Ok(None);
                }
                let clipped = bounds::caster_bounds(&self.geometry, caster_box, receivers);
                let Some(rect) = clipped.screen_rect(&scene.camera, self.extent) else { return Ok(None) };
                let rect = match self.inner {
                    None => Some(rect),
                    Some(inner) => inner.and_then(|inner| bounds::rect_intersection(rect, inner)),
                };
                let Some(rect) = rect else { return Ok(None) };
                (clipped.reach, rect)
            }
            _ => (Reach::Infinite, vk::Rect2D { offset: vk::Offset2D::default(), extent: self.extent }),
        };
        // Extruded on the GPU where the caster's mesh has tables: nothing to build.
        let caps = counting.zfail || matches!(caster.mesh.path, CastPath::TwoSided { .. });
        let stencil = counting.stencil == StencilMode::Reference;
        let in_object_space = light_in_object_space(&self.geometry, &object.transform);
        if let Some(extruded) = self
            .shadow_meshes
            .and_then(|meshes| meshes.volume(index, object.transform, in_object_space, reach, caps, stencil))
        {
            let volume = GpuVolume { caster: index, form: VolumeForm::Extruded(extruded), scissor };
            return Ok(Some((Some(volume), Source::ExtrudedOnGpu)));
        }
        // A volume is a function of the light, its reach and the caster's transform (and pose):
        // where none of them moved, its buffers still hold it (Doom 3's static shadows).
        let key = VolumeKey { light: self.geometry, reach, transform: object.transform };
        let mut push = VolumePush::new(object.transform, in_object_space, reach);
        let skinned = object.skin.is_some();
        let skinned_on_gpu = self.doubled.skinned_on_gpu(index);
        let source = match &slot.built {
            Some(built) if !skinned && built.key == key => Source::Reused,
            _ => {
                let mut scratch = self.scratch.mine();
                scratch.skinned_on_gpu = skinned_on_gpu;
                let built = volume_for(scene, caster, key, counting, &mut scratch);
                // The previous frame in this slot has finished (frames wait for their
                // fence): its buffers are free. A rigid caster's vertices are its mesh's.
                if skinned && !skinned_on_gpu {
                    slot.vertices.fill(self.gpu, built.volume_vertices)?;
                }
                slot.indices.fill_with(self.gpu, built.len, |out| built.write(out))?;
                slot.built = Some(BuiltVolume { key, ranges: built.ranges });
                if skinned_on_gpu {
                    // Skinned casters are rebuilt every frame: the scratch holds this one's pose.
                    let centroid = scratch.posed_centroid(caster.mesh.adjacency.vertex_count);
                    push.apex = centroid.unwrap_or_default().extend(1.0);
                }
                Source::Built
            }
        };
        let volume = slot.built.as_ref().filter(|built| built.ranges.iter().any(|r| r.count > 0)).map(|built| {
            let form = VolumeForm::Indexed { ranges: built.ranges.clone(), push };
            GpuVolume { caster: index, form, scissor }
        });
        Ok(Some((volume, source)))
    }
}

/// What a volume is built from, beside its caster: equal keys (and an unposed caster) give equal
/// volumes.
#[derive(Debug, Clone, Copy, PartialEq)]
struct VolumeKey {
    light: Light,
    reach: Reach,
    transform: Mat4,
}

/// The volume last written into a caster's buffers for one light, and what it was built from.
struct BuiltVolume {
    key: VolumeKey,
    ranges: Vec<IndexRange>,
}

/// Builds `caster`'s volume for `key` into `scratch` (its vertices where posed on the CPU) and
/// returns its index ranges in draw order (all empty: it casts nothing), with the lists they
/// are written from ([`VolumeIndices::write`]).
fn volume_for<'s>(
    scene: &Scene,
    caster: &'s Caster,
    key: VolumeKey,
    counting: Counting,
    scratch: &'s mut VolumeScratch,
) -> VolumeIndices<'s> {
    // Far caps close the volumes (point lights, and every clipped volume): drawn in both
    // methods, so that the background (depth 1) behind a volume never counts. Near caps for
    // z-fail, and for two-sided casters in z-pass too: a ray may pass one of their
    // triangles that the scene pass culled (seen from behind, as through the hole of an
    // open box), so the caster itself does not hide its near cap.
    scratch.volume.indices_only = true;
    build_volume_into(scene, caster, &key.light, key.reach, true, scratch);
    let near_cap = counting.zfail || matches!(caster.mesh.path, CastPath::TwoSided { .. });
    let VolumeScratch { volume, doubled, .. } = scratch;
    if !near_cap {
        volume.near_cap.clear();
    }
    // A mirroring transform (negative determinant) flips every winding on screen: turn
    // the triangles back so that the volume's faces still point out.
    if key.transform.determinant() < 0.0 {
        let lists = [&mut volume.sides, &mut volume.near_cap, &mut volume.far_cap].into_iter();
        for list in lists.chain(volume.repeated_walls.iter_mut().map(|(_, walls)| walls)) {
            list.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
        }
    }
    let once = (volume.sides.len() + volume.near_cap.len() + volume.far_cap.len()) as u32;
    let split = near_caps_split(scene, caster, key, counting).map(|as_drawn| {
        let lit = &volume.lit_faces;
        (NearCapSplit::of(lit, as_drawn), as_drawn)
    });
    let mut ranges = match split {
        None => vec![IndexRange { first: 0, count: once, times: 1, drawn_by: DrawnBy::Every }],
        // Laid out so that each culled pipeline's share is one run (`NearCapSplit::write_once`).
        Some((groups, _)) => {
            let ranges = groups.once_ranges(once).into_iter();
            ranges.map(|(first, count, drawn_by)| IndexRange { first, count, times: 1, drawn_by }).collect()
        }
    };
    let mut end = once;
    match counting.stencil {
        // The stencil's ops add 1 a fragment: a repeated list is drawn `times` times over.
        StencilMode::Reference => {
            end += volume.repeated_walls.iter().map(|(times, walls)| times * walls.len() as u32).sum::<u32>();
            ranges = vec![IndexRange { first: 0, count: end, times: 1, drawn_by: DrawnBy::Every }];
        }
        // The alpha counter draws it once, adding `times` k.
        StencilMode::Emulated => {
            for (times, walls) in &volume.repeated_walls {
                let count = walls.len() as u32;
                ranges.push(IndexRange { first: end, count, times: *times, drawn_by: DrawnBy::Every });
                end += walls.len() as u32;
            }
        }
    }
    VolumeIndices { volume, volume_vertices: doubled, ranges, len: end as usize, stencil: counting.stencil, near_caps: split }
}

/// Where `caster`'s near caps may each be left to the one pipeline that can see them
/// (`near_caps`), its faces drawn as the scene pass draws them; `None` where all are drawn by
/// both: z-fail, the stencil, a closed caster (no near caps in z-pass), a skinned or mirrored
/// one, or a material the depth buffer does not hold whole.
fn near_caps_split<'c>(scene: &Scene, caster: &'c Caster, key: VolumeKey, counting: Counting) -> Option<&'c [bool]> {
    let object = &scene.objects[caster.object];
    let opaque = matches!(scene.material_of(object).alpha_mode, AlphaMode::Opaque);
    let eligible = counting.split_near_caps
        && !counting.zfail
        && counting.stencil == StencilMode::Emulated
        && matches!(caster.mesh.path, CastPath::TwoSided { .. })
        && object.skin.is_none()
        && key.transform.determinant() > 0.0
        && opaque;
    eligible.then_some(caster.mesh.faces_as_drawn.as_slice())
}

/// A volume built in a scratch, its ranges, and how many indices they hold.
struct VolumeIndices<'s> {
    volume: &'s VolumeGeometry,
    /// A caster posed on the CPU: its posed vertices, doubled (else empty).
    volume_vertices: &'s [Vec4],
    ranges: Vec<IndexRange>,
    len: usize,
    /// Which counter the ranges were laid out for.
    stencil: StencilMode,
    /// Near caps split by the pipelines that see them: the groups, and which faces the scene
    /// pass draws as they are.
    near_caps: Option<(NearCapSplit, &'s [bool])>,
}

impl VolumeIndices<'_> {
    /// The indices in draw order into `out` (`len` long): sides, caps, then the repeated
    /// walls (once each for the alpha counter, `times` times over for the stencil).
    fn write(&self, out: &mut [u32]) {
        let volume = self.volume;
        let mut at = 0;
        let once: [&[u32]; 3] = match self.near_caps {
            None => [&volume.sides, &volume.near_cap, &volume.far_cap],
            Some((groups, as_drawn)) => {
                at = groups.write_once(volume, as_drawn, out);
                [&[]; 3]
            }
        };
        let repeated = volume.repeated_walls.iter().flat_map(|(times, walls)| {
            let times = if self.stencil == StencilMode::Reference { *times as usize } else { 1 };
            std::iter::repeat(walls.as_slice()).take(times)
        });
        for list in once.into_iter().chain(repeated) {
            out[at..at + list.len()].copy_from_slice(list);
            at += list.len();
        }
    }
}

