//! The scene's meshes on the GPU and the lit scene pass every seed 001 shadow draws first:
//! skinned objects are skinned on the GPU by the passes' skinned pipelines, from the frame's
//! joint palettes (`shaders/joint_palettes.glsl`), or posed on the CPU (`--skinning cpu`).

use std::sync::Arc;

use super::lod::CasterLods;
use super::receiver::ReceiverPlane;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::pipeline::{FixedFunction, PipelineDesc, StencilState, VertexLayout};
use crate::render::object_push::draw_order;
use crate::render::plan::{MaterialVariant, PassKinds, PlannedPass, SetRole};
use crate::render::Pipeline;
use crate::render::{object_push, FrameRecorder, GpuScene, IndexedDraw, LightPush, Skinning, OBJECT_PUSH_BYTES};
use crate::scene::Scene;
use crate::shaders;
use crate::technique::material_variants::with_surface_variants;

/// The sets of every pass that draws the scene's objects (the scene, the casters): the frame's
/// uniforms and joint palettes, the material (casters cut out by MASK).
pub fn scene_sets<S>() -> [SetRole<S>; 2] {
    [SetRole::Frame, SetRole::Material]
}

/// A lit scene pipeline: Lambert + ambient, static or GPU-skinned (`lit.vert`'s skinned twin),
/// with an optional stencil write (the planar reference marks receivers).
pub fn scene_desc(name: &'static str, skinned: bool, stencil: Option<StencilState>) -> PipelineDesc {
    PipelineDesc {
        name,
        vertex_shader: if skinned { shaders::LIT_SKINNED_VERT } else { shaders::LIT_VERT },
        fragment_shader: shaders::LIT_FRAG,
        vertex_layout: if skinned { VertexLayout::SKINNED_SCENE } else { VertexLayout::SCENE },
        fixed: FixedFunction { stencil, ..FixedFunction::OPAQUE },
        push_constant_bytes: OBJECT_PUSH_BYTES,
    }
}

/// A scene pass: receivers drawn with `receiver`, other static objects with `other` (left out
/// when it is the same pipeline), skinned objects with `skinned`; `push` says which alpha each
/// writes.
pub fn scene_pass<K: PassKinds>(
    receiver: PipelineDesc,
    other: PipelineDesc,
    skinned: PipelineDesc,
    push: &'static str,
    draw: K::Draw,
) -> PlannedPass<K> {
    named_scene_pass("scene", receiver, other, skinned, push, draw)
}

/// [`scene_pass`] under another name (the additive loop's ambient, shading and transparent
/// passes draw the objects the same way).
pub fn named_scene_pass<K: PassKinds>(
    name: impl Into<std::borrow::Cow<'static, str>>,
    receiver: PipelineDesc,
    other: PipelineDesc,
    skinned: PipelineDesc,
    push: impl Into<std::borrow::Cow<'static, str>>,
    draw: K::Draw,
) -> PlannedPass<K> {
    let distinct = other.name != receiver.name;
    let mut pass = PlannedPass::own(name, receiver, draw, push).with_sets(&scene_sets());
    if distinct {
        pass = pass.or_pipeline(other.clone());
    }
    let pass = with_surface_variants(pass.or_pipeline(skinned.clone()), &other);
    with_surface_variants(pass, &skinned)
}

/// The lit scene pass of the blob and shadow-texture techniques: every object alike, alpha 1.
pub fn lit_scene_pass<K: PassKinds>(draw: K::Draw) -> PlannedPass<K> {
    let scene = scene_desc("scene", false, None);
    let skinned = scene_desc("scene (skinned)", true, None);
    scene_pass(scene.clone(), scene, skinned, "object transform and colour, alpha 1", draw)
}

/// The scene's meshes on the GPU (a skinned object's bind pose, skinning on the GPU): what
/// every planar technique draws its lit pass (and its casters) from.
pub(crate) struct SceneMeshes {
    pub meshes: GpuScene,
}

impl SceneMeshes {
    /// `skinning`: where skinned objects are posed (on the CPU, every object is drawn from the
    /// scene's meshes, re-posed when the pose changes: `follow_pose`).
    pub fn upload(gpu: &Arc<Gpu>, scene: &Scene, skinning: Skinning) -> Result<Self> {
        Ok(SceneMeshes { meshes: GpuScene::upload_for(gpu, scene, skinning)? })
    }

    /// This frame's pose in frame slot `slot`'s copies of the objects posed on the CPU (those
    /// skinned on the GPU read the frame's palettes).
    pub fn follow_pose(&mut self, gpu: &Arc<Gpu>, scene: &Scene, slot: usize) -> Result<()> {
        self.meshes.follow_pose(gpu, scene, slot)
    }

    /// Draws object `index` with `static_pipeline` or, skinned on the GPU, `skinned_pipeline`,
    /// with its material at set 1 (every planar pass has `scene_sets`).
    pub fn draw<T: bytemuck::Pod>(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        index: usize,
        pipelines: [&Pipeline; 2],
        push: &T,
    ) {
        self.draw_caster(rec, scene, index, pipelines, push, None);
    }

    /// [`SceneMeshes::draw`], with the caster's simplified triangles in place of its own when
    /// `lod` holds them (same vertices, so the same pipelines).
    pub fn draw_caster<T: bytemuck::Pod>(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        index: usize,
        [static_pipeline, skinned_pipeline]: [&Pipeline; 2],
        push: &T,
        lod: Option<&CasterLods>,
    ) {
        let object = &scene.objects[index];
        let (pipeline, mesh) = match self.meshes.skinned_mesh(index) {
            Some(bind_pose) => (skinned_pipeline, bind_pose),
            None => (static_pipeline, &self.meshes.meshes[object.mesh]),
        };
        rec.bind(pipeline);
        rec.bind_material(pipeline, self.meshes.materials.set(object.material));
        rec.push(pipeline, push);
        match lod.and_then(|l| l.per_object.get(index)).and_then(Option::as_ref) {
            Some(simplified) => {
                // The simplified indices count from the mesh's first vertex, wherever its
                // buffer holds it.
                let (vertices, vertex_offset) = mesh.vertices_in(rec.slot());
                rec.bind_indexed(vertices, &simplified.indices);
                rec.draw_indexed(IndexedDraw { vertex_offset, ..IndexedDraw::range(0, simplified.index_count) });
            }
            None => rec.draw_mesh(mesh),
        }
    }

    /// The [static, skinned] pipelines that cast object `index`'s shadow in `pass`: their
    /// alpha-mask variants for a MASK material, else `opaque`.
    pub fn caster_pipelines<'p, K: PassKinds>(
        scene: &Scene,
        index: usize,
        pass: &PlannedPass<K>,
        pipelines: &[&'p Pipeline],
        opaque: [&'p Pipeline; 2],
    ) -> [&'p Pipeline; 2] {
        let variant = MaterialVariant::for_caster(scene.material_of(&scene.objects[index]));
        opaque.map(|p| pass.variant(pipelines, p, variant))
    }

    /// Draws the scene pass (see [`scene_pass`]) with `pipelines` as the recorder hands them
    /// over: every object with its transform and colour, receivers writing alpha
    /// `receiver_alpha` and everything else alpha 1.
    pub fn draw_scene<K: PassKinds>(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        plane: &ReceiverPlane,
        pass: &PlannedPass<K>,
        pipelines: &[&Pipeline],
        receiver_alpha: f32,
    ) -> Result<()> {
        self.draw_scene_for(rec, scene, plane, pass, pipelines, receiver_alpha, None)
    }

    /// [`SceneMeshes::draw_scene`]; with `light`, each draw pushes which of the frame's lights
    /// it shades (`LightPush`, a per-light pass).
    #[allow(clippy::too_many_arguments)]
    pub fn draw_scene_for<K: PassKinds>(
        &self,
        rec: &mut FrameRecorder,
        scene: &Scene,
        plane: &ReceiverPlane,
        pass: &PlannedPass<K>,
        pipelines: &[&Pipeline],
        receiver_alpha: f32,
        light: Option<u8>,
    ) -> Result<()> {
        let fixed = pipelines.len() - pass.variants.iter().filter(|v| v.is_some()).count();
        let (receiver, other, skinned) = match pipelines[..fixed.min(pipelines.len())] {
            [receiver, skinned] => (receiver, receiver, skinned),
            [receiver, other, skinned] => (receiver, other, skinned),
            _ => return Err(Error::Internal(format!("the scene pass has {} pipelines", pipelines.len()))),
        };
        for index in draw_order(scene) {
            let object = &scene.objects[index];
            if !pass.only.draws(scene.material_of(object)) {
                continue;
            }
            let on_plane = plane.receivers[index];
            let alpha = if on_plane { receiver_alpha } else { 1.0 };
            let push = object_push(scene, object, alpha);
            // Receivers keep the receiver pipeline in both paths (the reference's marks stencil
            // 0, and a cut-out there would leave the emulated and reference paths different);
            // every other static object is drawn as its material needs.
            let variant = MaterialVariant::for_surface(scene.material_of(object));
            let chosen = if on_plane { receiver } else { pass.variant(pipelines, other, variant) };
            let skinned = pass.variant(pipelines, skinned, variant);
            match light {
                Some(light) => {
                    let push = LightPush { object: push, light: [u32::from(light), 0, 0, 0] };
                    self.draw(rec, scene, index, [chosen, skinned], &push)
                }
                None => self.draw(rec, scene, index, [chosen, skinned], &push),
            }
        }
        Ok(())
    }
}
