//! nostencil: a Vulkan renderer for mobile-class limits, whose main framebuffer has no stencil.
//! Every stencil effect is rebuilt on the alpha channel with fixed-function blend states, and
//! checked against a reference path that uses a real stencil.
//!
//! # Start here
//!
//! This page is the whole library a port calls; everything else is private to the crate.
//! 1. A [`Gpu`] ([`GpuOptions`] chooses the device and the validation layer).
//! 2. A [`Scene`]: [`builtin_scene`] (the names are in [`BUILTIN_SCENES`]), or
//!    [`scene_from_gltf`] / [`scene_and_warnings_from_gltf`] for a `.gltf`/`.glb` file.
//! 3. A technique, by name ([`technique`]; all of them in [`TECHNIQUES`]), and its
//!    [`RenderOptions`]: size, samples, [`StencilMode`] and each family's options
//!    ([`ShadowVolumeOptions`], [`PlanarOptions`], [`CartoonOptions`], [`ShadowAtlasOptions`]).
//! 4. A frame: [`render_scene`] for one, or [`Technique::build`] for a [`SceneRenderer`] that
//!    renders frame after frame of a moving scene (`frame_with`). A [`TechniqueFrame`] holds
//!    the image ([`write_png`] writes it), its per-pass [`FrameCounters`] and the technique's
//!    statistics ([`stats`]). `keep_on_gpu(true)` leaves frames on the GPU instead of
//!    reading them back.
//! 5. Counters by pass: [`FrameCounters::drawing`] finds the passes in which a technique drew
//!    one of its own draw kinds ([`draws`]), typed; [`FrameCounters::passes`] lists them all
//!    in the order they ran.
//!
//! Every type these signatures name is on this page or in its modules: a scene's data in
//! [`model`], the render passes' traffic and the CPU's phases in [`counters`], each technique's
//! statistics in [`stats`] and its draw kinds in [`draws`].
//!
//! ```
//! use nostencil::draws::VolumeDraw;
//! use nostencil::{render_scene, technique, Gpu, GpuOptions, RenderOptions, StencilMode};
//!
//! # fn main() -> nostencil::Result<()> {
//! let gpu = Gpu::new(&GpuOptions::default())?;
//! let scene = nostencil::builtin_scene("box")?;
//! let options = RenderOptions {
//!     width: 64,
//!     height: 48,
//!     technique: technique("shadow-volume")?,
//!     stencil: StencilMode::Emulated,
//!     ..RenderOptions::default()
//! };
//! let frame = render_scene(&gpu, &scene, &options)?;
//! assert_eq!(frame.output.image.dimensions(), (64, 48));
//! // Per measured pass: draws, fragments, samples passed, GPU time.
//! // The first light's volumes (a draw kind matches whatever its fields hold).
//! let any_volumes = VolumeDraw::Volumes { alpha: 0.0, light: 0, clear_stencil: false };
//! let volumes = frame.output.counters.drawing(any_volumes).next().expect("a pass");
//! assert!(volumes.samples_passed > 0);
//! # Ok(())
//! # }
//! ```
//!
//! `examples/` holds two programs built on this page alone (a glTF file to a PNG, and per-pass
//! counters printed) and one sample per technique in plain ash on the [`sample`] base class
//! (docs/porting.md). How the crate is built inside: docs/architecture.md; adding a technique:
//! docs/adding-a-technique.md.
//!
//! *Seed NNN*, in these pages and the code's comments, names document NNN of the five the
//! techniques come from (docs/sources.md, "The five documents the techniques come from"): seed
//! 000 is Hall's alpha-counted shadow volumes, 001 the planar shadows, 002 the cartoon
//! silhouettes, 003 the stencil outline, 004 Ryu and Oh's shadow textures.

// Raw Vulkan lives in gpu/, frame/ and render/, and in layer/ (the fill-rate layer is raw Vulkan
// by nature: it sits between a program and its driver); each unsafe block says why it is sound.
#![warn(clippy::undocumented_unsafe_blocks)]

// Everything below the façade is private to the crate: a port sees only what this page
// documents. The tests that reach inside (tests/inside/) are compiled into the crate's own test
// build, where `nostencil::` names the crate itself, as it does for the integration tests.
#[cfg(test)]
extern crate self as nostencil;
#[cfg(test)]
#[path = "../tests/inside/common.rs"]
mod common;
#[cfg(test)]
#[path = "../tests/inside/mod.rs"]
mod inside;

// Everything below the façade is private to the crate. What only the tests use is
// `#[cfg(test)]` where it is defined, imports included.
mod frame;
mod gpu;
mod mesh;
mod names;
mod pipeline;
mod profile;
mod render;
mod scene;
mod shaders;
mod technique;
mod viewer;

#[doc(hidden)]
pub mod cli;
pub mod error;
pub mod sample;

pub use error::{Error, Result};
pub use frame::{write_png, StencilMode};
pub use gpu::{DeviceChoice, Gpu, GpuOptions, ValidationChecks};
pub use render::{FrameCounters, FrameOutput, PassCounters};

/// The JSON report an HTML page written by `--html` embeds (equal to `--format json`'s), read
/// back from the page's text: what a dashboard reads from the same file a person opens.
pub use profile::html::page::embedded_json;

/// What a frame's counters hold beyond each pass's figures ([`FrameCounters`]'s fields).
pub mod counters {
    pub use crate::frame::render_pass::{AttachmentDesc, AttachmentTraffic, RenderPassTraffic};
    pub use crate::gpu::frame_submission::CpuPhases;
    pub use crate::render::instances::{RenderPassInstance, RenderPassSums};
}

/// The data a [`Scene`] holds: meshes, materials, textures and skins, as a glTF file or a
/// built-in scene fills them in.
pub mod model {
    pub use crate::mesh::MeshData;
    pub use crate::scene::model::{
        AlphaMode, Filter, LightKind, Material, Sampler, TextureRef, TextureRgba8, TextureTransform, Wrap,
    };
    pub use crate::scene::objects::SceneMesh;
    pub use crate::scene::SceneSkin;
}
pub use scene::{
    builtin_scene, builtin_scene_at, scene_and_warnings_from_gltf, scene_from_gltf, Camera, Light, Scene, SceneLight,
    SceneObject, BUILTIN_SCENES, MAX_LIGHTS,
};
pub use technique::{
    by_name as technique, render_scene, AtlasBake, CartoonOptions, FrameStats, GivenPlane, InkStyle, InkStyles,
    LightMode, Normalize, OutlineMethod, PlanarOptions, RenderOptions, SceneRenderer, Seams, ShadowAtlasOptions,
    ShadowKind, ShadowMode, ShadowTone, ShadowVolumeOptions, SilhouetteMethod, Technique, TechniqueFrame,
    TextureShadowOn, VolumeExtrusion, VolumeMethod, TECHNIQUES,
};

/// What each technique reports about a frame, beyond its counters
/// ([`TechniqueFrame::stats`]).
pub mod stats {
    pub use crate::technique::shadow_atlas::atlas::AtlasSource;
    pub use crate::technique::shadow_atlas::stats::{AtlasInfo, PageStats};
    pub use crate::technique::shadow_volume::stats::{CasterReport, LightReport};
    pub use crate::technique::{CartoonStats, PlanarStats, ShadowAtlasStats, ShadowVolumeStats};
}

/// The draws each technique records itself, to find their passes' counters by type
/// ([`FrameCounters::drawing`]).
pub mod draws {
    pub use crate::render::plan::DrawKind;
    pub use crate::technique::ink::recipes::InkDraw;
    pub use crate::technique::outline::kinds::OutlineDraw;
    pub use crate::technique::planar::blob::BlobDraw;
    pub use crate::technique::planar::flattened::PlanarDraw;
    pub use crate::technique::planar::shadow_texture::TextureDraw;
    pub use crate::technique::shadow_atlas::passes::AtlasDraw;
    pub use crate::technique::shadow_volume::recipes::VolumeDraw;
    pub use crate::technique::xray::XRayDraw;
}
