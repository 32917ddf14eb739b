//! The shadow-volume renderer: casters prepared once, each volume built again only when its
//! light, reach or caster moved (else the buffers of the frames before are drawn again), written
//! into buffers kept from frame to frame (made again only when a volume outgrows them), drawn by
//! the plan of `recipes`. What a frame reports is in `stats`.

use std::sync::Arc;

use ash::vk;
use glam::Vec4;

use super::alpha_counter;
use super::bounds;
use super::casters::{choose_zfail, prepare_casters, Caster, VolumeScratch};
use super::culling::{self, Culling, KeptCulling};
use super::doubled::{Doubled, DoubledVertices};
use super::frame_volumes::Counting;
use super::gpu_extrusion::{ShadowMeshes, VolumePush};
use super::recipes::SATURATION_PROBE;
use super::recipes::{is_extruded, VolumeDraw, VolumeKinds, VolumeSet};
pub use super::stats::{CasterReport, LightReport, ShadowVolumeStats};
use super::stats::{
    MEASURED_BY_APPLY, MEASURED_BY_MASK, MEASURED_BY_PROBE, NOT_COUNTED_REFERENCE, NOT_MEASURED, NOT_MEASURED_ADDITIVE,
    NOT_MEASURED_NO_ATOMICS,
};
use super::volume_uploads::{upload_volumes, GpuVolume, LitBy, Uploads, VolumeBuffers, VolumeForm};
use crate::error::{Error, Result};
use crate::frame::StencilMode;
use crate::gpu::descriptors::{Binding, DescriptorSet};
use crate::gpu::memory::Buffer;
use crate::gpu::Gpu;
use crate::pipeline::recipes::STENCIL_COUNT_ZERO;
use crate::render::jobs::PerWorker;
use crate::render::passes::{Clear, Passes};
use crate::render::per_slot::slot_copy;
use crate::render::plan::{Draws, PlannedPass, Scissor};
use crate::render::Pipeline;
use crate::render::{FrameOutput, FrameRecorder, GpuScene, IndexedDraw, Renderer};
use crate::scene::Scene;
use crate::technique::frame_renderer::BuildContext;
use crate::technique::interface::{FrameStats, RenderOptions};
use crate::technique::options::{Normalize, ShadowMode, ShadowVolumeOptions, VolumeExtrusion, VolumeMethod};
use crate::technique::shadow_tone::ShadowTone;
use crate::technique::unit::Prepared;

/// What is worked out from the scene before the frame is planned: the casters, whose volumes
/// decide whether `auto` counts z-fail for this camera.
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
pub fn make(ctx: BuildContext<'_>, scene: &Scene, setup: VolumeSetup) -> Result<ShadowVolumePasses> {
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
            let mut bindings =
                vec![Binding::InputAttachment { view: drawn_colour.view, layout: vk::ImageLayout::GENERAL }];
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
                        let draw = IndexedDraw::range(range.first, range.count);
                        rec.draw_indexed(IndexedDraw { vertex_offset, first_instance: range.times, ..draw });
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
    /// (additive); the reference's stencil count starts at its zero.
    fn clear(&self) -> Clear {
        let alpha = match self.mode {
            ShadowMode::Modulate => 0.0,
            ShadowMode::Additive => 1.0,
        };
        Clear { alpha, stencil: STENCIL_COUNT_ZERO }
    }

    fn stats(&mut self, output: &FrameOutput, _scene: &Scene) -> Box<dyn FrameStats> {
        let mut stats = self.stats.clone();
        let pixels = f64::from(output.counters.width) * f64::from(output.counters.height);
        let samples = pixels * f64::from(output.counters.samples.max(1));
        for (index, light) in stats.lights.iter_mut().enumerate() {
            // The volume passes drawn for the light (the plan's `for_light`): each light's in
            // the additive loop; the modulate frame has one set, the primary light's.
            if self.mode == ShadowMode::Modulate && index != self.primary {
                continue;
            }
            let any_volumes = VolumeDraw::Volumes { alpha: 0.0, light: 0, clear_stencil: false };
            let for_light = u8::try_from(index).ok();
            let passes: Vec<_> = output.counters.drawing(any_volumes).filter(|p| p.light == for_light).collect();
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
