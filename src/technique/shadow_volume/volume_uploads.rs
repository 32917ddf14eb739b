//! Where a frame's volumes go: per light, one job per caster builds its volume (`frame_volumes`)
//! where its light, reach or pose moved, and writes it into that caster's buffers, kept from
//! frame to frame; or, where its mesh has tables, leaves it to the vertex shader. The renderer
//! draws what it returns.

use std::sync::Arc;

use ash::vk;

use super::bounds;
use super::casters::{light_in_object_space, Caster, VolumeScratch};
use super::culling::Culling;
use super::doubled::DoubledVertices;
use super::frame_volumes::{volume_for, BuiltVolume, Counting, IndexRange, VolumeKey};
use super::gpu_extrusion::{ExtrudedVolume, ShadowMeshes, VolumePush};
use super::near_caps::DrawnBy;
use crate::error::Result;
use crate::frame::StencilMode;
use crate::gpu::memory::ReusedBuffer;
use crate::gpu::Gpu;
use crate::mesh::caster::CastPath;
use crate::mesh::Reach;
use crate::render::jobs::{self, PerWorker};
use crate::render::plan::Scissor;
use crate::scene::{Light, Scene, SceneLight};
use crate::technique::options::ShadowVolumeOptions;

/// One caster's volume for this frame.
pub(super) struct GpuVolume {
    /// Its caster's index among the frame's casters: which of its light's buffers hold it.
    pub(super) caster: usize,
    pub(super) form: VolumeForm,
    /// Where it can shade: its walls are rasterised only there.
    pub(super) scissor: vk::Rect2D,
}

impl GpuVolume {
    /// Its near caps drawn by one counting pipeline (`near_caps`): those before the
    /// front-keeping pipeline's run, and those after the back-keeping one's.
    pub(super) fn near_caps_one_pipeline(&self) -> u64 {
        let VolumeForm::Indexed { ranges, .. } = &self.form else { return 0 };
        let run = |by: DrawnBy| ranges.iter().find(|r| r.drawn_by == by);
        match (run(DrawnBy::FrontKeeping), run(DrawnBy::BackKeeping), run(DrawnBy::Unculled)) {
            (Some(front), Some(back), Some(whole)) => u64::from(front.first + whole.count - back.count) / 3,
            _ => 0,
        }
    }
}

/// How a volume reaches the GPU.
pub(super) enum VolumeForm {
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
pub(super) struct VolumeBuffers {
    pub(super) vertices: ReusedBuffer,
    pub(super) indices: ReusedBuffer,
    /// What they hold.
    pub(super) built: Option<BuiltVolume>,
}

impl VolumeBuffers {
    pub(super) fn new() -> Self {
        VolumeBuffers {
            vertices: ReusedBuffer::new("shadow volume vertices", vk::BufferUsageFlags::VERTEX_BUFFER),
            indices: ReusedBuffer::new("shadow volume indices", vk::BufferUsageFlags::INDEX_BUFFER),
            built: None,
        }
    }
}

/// The light a frame's volumes are built for, its light scissor, and the casters it culls.
pub(super) struct LitBy<'a> {
    pub(super) light: &'a SceneLight,
    pub(super) rect: &'a Scissor,
    pub(super) culled: &'a Culling,
    /// Every object's posed world box, computed once a frame ([`bounds::object_boxes`]).
    pub(super) boxes: &'a [Option<bounds::Aabb>],
}

/// Where a light's volumes go: each caster's buffers, rewritten in place.
pub(super) struct Uploads<'a> {
    pub(super) gpu: &'a Arc<Gpu>,
    pub(super) buffers: &'a mut [VolumeBuffers],
    /// Counts the volumes whose buffers already held them.
    pub(super) reused: &'a mut usize,
    /// Counts the volumes extruded on the GPU.
    pub(super) extruded: &'a mut usize,
    /// What the jobs that build volumes write into, one per worker.
    pub(super) scratch: &'a PerWorker<VolumeScratch>,
    /// The casters' tables, where volumes are extruded on the GPU.
    pub(super) shadow_meshes: Option<&'a ShadowMeshes>,
    /// The doubled vertices uploaded at build (which skinned casters are skinned on the GPU).
    pub(super) doubled: &'a DoubledVertices,
}

/// How a caster's volume was had this frame, for the light's report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    Built,
    /// Its buffers already held it.
    Reused,
    ExtrudedOnGpu,
}

pub(super) fn upload_volumes(
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
