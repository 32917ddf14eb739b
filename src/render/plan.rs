//! Passes as data. A technique describes its frame as a [`PassPlan`]: an ordered list of
//! measured passes, each with its name, the pipelines it binds (built from the named recipes in
//! `pipeline::recipes`), what it draws and what it pushes. The renderer builds pipelines from
//! the plan, the recorder executes it in order, and `nostencil passes` prints it: the table a
//! port reads and the frame that runs come from the same value, and a test checks that every
//! frame runs exactly its plan.

use std::borrow::Cow;
use std::fmt;
use std::hash::Hash;

use ash::vk;
use glam::Vec4;

pub use super::materials::MaterialVariant;
use crate::pipeline::PipelineDesc;
use crate::render::pipeline_object::Pipeline;

/// A name a technique gives one of its own sets or render passes. Each technique declares an
/// enum of them, so that its plan and its renderer share one list and a `match` over it is
/// checked by the compiler: nothing is ever found by comparing strings.
pub trait Label: Copy + Eq + Hash + fmt::Debug + 'static {
    /// The name the `passes` table prints.
    fn label(self) -> &'static str;
}

/// A draw a technique records itself (volumes, ink quads, a bake...). It may carry the values
/// its draw needs (an alpha), so the renderer's `match` gets them with the kind.
pub trait DrawKind: Copy + PartialEq + fmt::Debug + 'static {
    /// What it draws, for the `passes` table.
    fn describe(self) -> &'static str;
}

/// The kinds of one technique's plan: its own draws, descriptor sets and render passes.
pub trait PassKinds: 'static {
    type Draw: DrawKind;
    type Set: Label;
    type Target: Label;
}

/// No draw, set or render pass of a technique's own: a type with no value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NoOwn {}

impl Label for NoOwn {
    fn label(self) -> &'static str {
        match self {}
    }
}

impl DrawKind for NoOwn {
    fn describe(self) -> &'static str {
        match self {}
    }
}

/// The kinds of a technique that draws only what the recorder draws (objects, full screen).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct RecorderOnly;

impl PassKinds for RecorderOnly {
    type Draw = NoOwn;
    type Set = NoOwn;
    type Target = NoOwn;
}

/// A label kept only by its name: the kinds of a plan as `passes` prints it and tests compare
/// it, whatever technique it came from (see [`PassPlan::named`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Name(pub &'static str);

impl Label for Name {
    fn label(self) -> &'static str {
        self.0
    }
}

impl DrawKind for Name {
    fn describe(self) -> &'static str {
        self.0
    }
}

/// The kinds of a plan kept by name ([`PassPlan::named`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Named;

impl PassKinds for Named {
    type Draw = Name;
    type Set = Name;
    type Target = Name;
}

/// What a pass draws, and so who draws it.
#[derive(Debug, Clone, PartialEq)]
pub enum Draws<D> {
    /// Every scene object, with its transform and base colour at `alpha` (`ObjectPush`): the
    /// recorder draws them, with each material's pipeline variant.
    Objects { alpha: f32 },
    /// One full-screen triangle, with `push` as its only input: the recorder draws it.
    FullScreen { push: Option<Vec4> },
    /// Draws the technique records itself; `push` says what it pushes, for the table.
    Own { draw: D, push: Cow<'static, str> },
}

impl<D: DrawKind> Draws<D> {
    pub fn describe(&self) -> String {
        match self {
            Draws::Objects { .. } => "objects".into(),
            Draws::FullScreen { .. } => "full screen".into(),
            Draws::Own { draw, .. } => draw.describe().into(),
        }
    }

    /// What the pass pushes, for the table.
    pub fn describe_push(&self) -> String {
        match self {
            Draws::Objects { alpha } => format!("object transform and colour, alpha {}", fmt_f32(*alpha)),
            Draws::FullScreen { push: None } => "-".into(),
            Draws::FullScreen { push: Some(v) } => {
                format!("({}, {}, {}, {})", fmt_f32(v.x), fmt_f32(v.y), fmt_f32(v.z), fmt_f32(v.w))
            }
            Draws::Own { push, .. } => push.to_string(),
        }
    }

    /// The same draws with the technique's kind mapped (kept by name for the table).
    fn map<E>(&self, f: impl FnOnce(D) -> E) -> Draws<E> {
        match self {
            Draws::Objects { alpha } => Draws::Objects { alpha: *alpha },
            Draws::FullScreen { push } => Draws::FullScreen { push: *push },
            Draws::Own { draw, push } => Draws::Own { draw: f(*draw), push: push.clone() },
        }
    }
}

/// Shortest text that reads back as the same f32.
pub fn fmt_f32(value: f32) -> String {
    format!("{value}")
}

/// Which render pass a pass draws into.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Target<T> {
    /// The frame's colour + depth render pass.
    Frame,
    /// A render pass of the technique's own (shadow map, shadow texture, atlas bake), recorded
    /// before the frame's.
    Offscreen(T),
}

impl<T: Label> Target<T> {
    /// The name the `passes` table prints.
    pub fn describe(self) -> &'static str {
        match self {
            Target::Frame => "frame",
            Target::Offscreen(target) => target.label(),
        }
    }
}

/// When a pass runs: most always do; some only in frames where a condition of their
/// technique's own holds (cached passes whose input did not change, a shadow the light cannot
/// cast), which the technique names and decides frame by frame (`Passes::conditions`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum When {
    Always,
    If(Condition),
}

/// A condition a technique's passes run under, named by the technique: equal names are the
/// same condition.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Condition {
    /// What it is, as the `passes` table says it ("when the light is above the plane").
    pub describe: &'static str,
    /// The light it is about, in a per-light loop (one condition per light).
    pub light: Option<u8>,
}

impl Condition {
    pub const fn named(describe: &'static str) -> Self {
        Condition { describe, light: None }
    }

    /// The condition for light `light` (an index into the scene's lights).
    pub const fn for_light(self, light: u8) -> Self {
        Condition { light: Some(light), ..self }
    }
}

impl When {
    /// Whether passes conditioned on `self` run in a frame where `conditions` hold.
    pub fn holds_in(self, conditions: &[When]) -> bool {
        self == When::Always || conditions.contains(&self)
    }

    pub fn describe(&self) -> &'static str {
        match self {
            When::Always => "every frame",
            When::If(condition) => condition.describe,
        }
    }
}

/// Descriptor sets a pass binds, by role; the technique supplies the sets themselves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SetRole<S> {
    /// The frame's uniforms (camera, light) at set 0.
    Frame,
    /// A set of the technique's own (its counter input, toon ramps, joint palette...).
    Own(S),
    /// The drawn object's material (`render::materials`), always at set `MATERIAL_SET`, bound
    /// per object.
    Material,
}

/// One measured pass of a technique whose own draws, sets and render passes are the kinds `K`.
#[derive(Debug, Clone)]
pub struct PlannedPass<K: PassKinds = Named> {
    /// The name its counters are reported under.
    pub name: Cow<'static, str>,
    /// Pipelines bound in this pass, first the main one; alternatives follow (for example the
    /// skinned variant of an object pipeline, bound only for skinned objects).
    pub pipelines: Vec<PipelineDesc>,
    /// Per pipeline: the material variant it is bound for, `None` for those every frame binds.
    pub variants: Vec<Option<MaterialVariant>>,
    /// Per pipeline: the pipeline it stands in for (a variant's opaque pipeline; its own name
    /// for the others).
    pub bases: Vec<&'static str>,
    /// Descriptor sets, by role, at sets 0, 1, ... of every pipeline of the pass.
    pub sets: Vec<SetRole<K::Set>>,
    pub draws: Draws<K::Draw>,
    pub target: Target<K::Target>,
    pub when: When,
    /// Reads the colour target written by earlier passes of its subpass (a by-region barrier
    /// first: on a tiler, the read stays in tile memory).
    pub reads_colour: bool,
    /// Drawn inside the technique's scissor for the frame (`Passes::scissor`) rather than
    /// over the whole frame.
    pub scissored: bool,
    /// The light (index into the scene's lights) a pass of a per-light loop is for: its
    /// scissor is that light's, and an object pass pushes the index after `ObjectPush`.
    pub light: Option<u8>,
    /// Which objects an object pass draws.
    pub only: Only,
}

/// Which objects an object pass draws, by how their material blends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Only {
    #[default]
    All,
    /// Opaque and cut-out materials: the per-light loop's passes (depth-equal shading needs
    /// the depth a surface wrote).
    Opaque,
    /// Blended materials: drawn after the loop, lit by every light.
    Blended,
}

impl Only {
    /// Whether a pass with `self` draws an object of `material`.
    pub fn draws(self, material: &crate::scene::model::Material) -> bool {
        let blended = matches!(
            MaterialVariant::for_surface(material),
            Some(MaterialVariant::Blend | MaterialVariant::BlendDoubleSided)
        );
        match self {
            Only::All => true,
            Only::Opaque => !blended,
            Only::Blended => blended,
        }
    }
}

/// Where a scissored pass draws this frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Scissor {
    /// The whole frame.
    Frame,
    /// Inside these rectangles, which must not overlap: a full-screen pass is drawn once in each
    /// (none: the pass draws nothing this frame).
    Rects(Vec<vk::Rect2D>),
}

impl<K: PassKinds> PlannedPass<K> {
    /// A pass into the frame that draws with one pipeline, every frame.
    pub fn new(name: impl Into<Cow<'static, str>>, pipeline: PipelineDesc, draws: Draws<K::Draw>) -> Self {
        PlannedPass {
            name: name.into(),
            bases: vec![pipeline.name],
            pipelines: vec![pipeline],
            variants: vec![None],
            sets: Vec::new(),
            draws,
            target: Target::Frame,
            when: When::Always,
            reads_colour: false,
            scissored: false,
            light: None,
            only: Only::All,
        }
    }

    /// A pass of draws the technique records itself (`push` describes what it pushes).
    pub fn own(
        name: impl Into<Cow<'static, str>>,
        pipeline: PipelineDesc,
        draw: K::Draw,
        push: impl Into<Cow<'static, str>>,
    ) -> Self {
        Self::new(name, pipeline, Draws::Own { draw, push: push.into() })
    }

    /// A pass into a render pass of the technique's own, before the frame's: the technique
    /// records it whole (begins and ends that render pass), so its draws are always its own.
    pub fn offscreen(
        name: impl Into<Cow<'static, str>>,
        pipeline: PipelineDesc,
        draw: K::Draw,
        push: impl Into<Cow<'static, str>>,
        target: K::Target,
    ) -> Self {
        PlannedPass { target: Target::Offscreen(target), ..Self::own(name, pipeline, draw, push) }
    }

    /// A pass that draws every scene object with its colour at `alpha`.
    pub fn objects(name: impl Into<Cow<'static, str>>, pipeline: PipelineDesc, alpha: f32) -> Self {
        Self::new(name, pipeline, Draws::Objects { alpha })
    }

    /// A full-screen pass with a constant push.
    pub fn full_screen(name: impl Into<Cow<'static, str>>, pipeline: PipelineDesc, push: Vec4) -> Self {
        Self::new(name, pipeline, Draws::FullScreen { push: Some(push) })
    }

    /// An offscreen pass that binds no pipeline (copies, blits), every frame.
    pub fn commands(name: impl Into<Cow<'static, str>>, draw: K::Draw, target: K::Target) -> Self {
        PlannedPass {
            name: name.into(),
            pipelines: Vec::new(),
            variants: Vec::new(),
            bases: Vec::new(),
            sets: Vec::new(),
            draws: Draws::Own { draw, push: "-".into() },
            target: Target::Offscreen(target),
            when: When::Always,
            reads_colour: false,
            scissored: false,
            light: None,
            only: Only::All,
        }
    }

    pub fn with_sets(mut self, sets: &[SetRole<K::Set>]) -> Self {
        self.sets = sets.to_vec();
        self
    }

    /// Adds an alternative pipeline (bound for some draws of the pass).
    pub fn or_pipeline(mut self, pipeline: PipelineDesc) -> Self {
        self.bases.push(pipeline.name);
        self.pipelines.push(pipeline);
        self.variants.push(None);
        self
    }

    /// Adds a pipeline that stands in for the pipeline named `base` for objects whose material
    /// needs `variant`.
    pub fn or_variant(mut self, variant: MaterialVariant, base: &'static str, pipeline: PipelineDesc) -> Self {
        self.pipelines.push(pipeline);
        self.variants.push(Some(variant));
        self.bases.push(base);
        self
    }

    /// The pipeline of `pipelines` (this pass's, as the recorder hands them over) that draws in
    /// place of `base` a material needing `variant`: that variant, or `base` itself when the
    /// material needs none or the pass has no such variant.
    pub fn variant<'p>(
        &self,
        pipelines: &[&'p Pipeline],
        base: &'p Pipeline,
        variant: Option<MaterialVariant>,
    ) -> &'p Pipeline {
        self.variant_index(base.desc.name, variant).and_then(|i| pipelines.get(i).copied()).unwrap_or(base)
    }

    /// The index in `pipelines` of the variant `variant` of the pipeline named `base`.
    pub fn variant_index(&self, base: &str, variant: Option<MaterialVariant>) -> Option<usize> {
        let wanted = variant?;
        (0..self.pipelines.len()).find(|&i| self.variants[i] == Some(wanted) && self.bases[i] == base)
    }

    pub fn when(mut self, when: When) -> Self {
        self.when = when;
        self
    }

    pub fn reading_colour(mut self) -> Self {
        self.reads_colour = true;
        self
    }

    /// Drawn inside the technique's scissor for the frame (see [`Passes::scissor`](super::passes::Passes::scissor)).
    pub fn for_light(mut self, light: u8) -> Self {
        self.light = Some(light);
        self
    }

    pub fn only(mut self, only: Only) -> Self {
        self.only = only;
        self
    }

    pub fn scissored(mut self) -> Self {
        self.scissored = true;
        self
    }

    /// The pass's main pipeline (none for a pass of transfer commands).
    #[cfg(test)]
    pub fn pipeline(&self) -> Option<&PipelineDesc> {
        self.pipelines.first()
    }

    /// What the pass pushes, for the table.
    pub fn describe_push(&self) -> String {
        match (&self.draws, self.light) {
            (Draws::Objects { .. }, Some(light)) => format!("{}, light {light}", self.draws.describe_push()),
            _ => self.draws.describe_push(),
        }
    }

    /// This pass with its kinds kept by name (see [`PassPlan::named`]).
    pub fn named(&self) -> PlannedPass<Named> {
        PlannedPass {
            name: self.name.clone(),
            pipelines: self.pipelines.clone(),
            variants: self.variants.clone(),
            bases: self.bases.clone(),
            sets: self
                .sets
                .iter()
                .map(|role| match *role {
                    SetRole::Frame => SetRole::Frame,
                    SetRole::Own(set) => SetRole::Own(Name(set.label())),
                    SetRole::Material => SetRole::Material,
                })
                .collect(),
            draws: self.draws.map(|draw| Name(draw.describe())),
            target: match self.target {
                Target::Frame => Target::Frame,
                Target::Offscreen(target) => Target::Offscreen(Name(target.label())),
            },
            when: self.when,
            reads_colour: self.reads_colour,
            scissored: self.scissored,
            light: self.light,
            only: self.only,
        }
    }
}

/// A technique's frame, pass by pass, in the order they run.
#[derive(Debug, Clone)]
pub struct PassPlan<K: PassKinds = Named> {
    pub passes: Vec<PlannedPass<K>>,
}

impl<K: PassKinds> Default for PassPlan<K> {
    fn default() -> Self {
        PassPlan { passes: Vec::new() }
    }
}

impl<K: PassKinds> PassPlan<K> {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn push(&mut self, pass: PlannedPass<K>) -> &mut Self {
        self.passes.push(pass);
        self
    }

    pub fn extend(&mut self, passes: impl IntoIterator<Item = PlannedPass<K>>) -> &mut Self {
        self.passes.extend(passes);
        self
    }

    /// The plan with its kinds kept by name: what `passes` prints, what a test compares, and
    /// what the object-safe `Technique` interface hands out, whatever the technique.
    pub fn named(&self) -> PassPlan<Named> {
        PassPlan { passes: self.passes.iter().map(PlannedPass::named).collect() }
    }

    /// (pass name, pipeline labels) of every pass that runs in a frame where `holds(when)`:
    /// what the recorder must report having run.
    /// Material variants are left out: see [`PassPlan::expected_trace_with`].
    #[cfg(test)]
    pub fn expected_trace(&self, holds: impl Fn(When) -> bool) -> Vec<(String, Vec<&'static str>)> {
        self.expected_trace_with(holds, |_| false)
    }

    /// As [`PassPlan::expected_trace`] for a scene whose objects need the material variants for
    /// which `needed` holds (in plan order: the recorder reports a pass's pipelines so).
    #[cfg(test)]
    pub fn expected_trace_with(
        &self,
        holds: impl Fn(When) -> bool,
        needed: impl Fn(MaterialVariant) -> bool,
    ) -> Vec<(String, Vec<&'static str>)> {
        self.passes
            .iter()
            .filter(|p| holds(p.when))
            .map(|p| {
                // A pass of blended objects draws each through a blend variant: of its own
                // pipelines only the main one is bound (by the recorder, as the pass opens).
                let fixed = |i: usize| p.only != Only::Blended || i == 0;
                let bound =
                    p.pipelines.iter().zip(&p.variants).enumerate().filter(|(i, (_, v))| v.map_or(fixed(*i), &needed));
                (p.name.to_string(), bound.map(|(_, (d, _))| d.name).collect())
            })
            .collect()
    }
}
