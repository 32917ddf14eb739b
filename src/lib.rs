//! nostencil: a Vulkan renderer for mobile-class limits, whose main framebuffer has no stencil.
//! Every stencil effect is rebuilt on the alpha channel with fixed-function blend states, and
//! checked against a reference path that uses a real stencil.
//!
//! # Use from a port
//!
//! A scene goes in, a technique's renderer is built for it once, and frames come out with their
//! fill-rate counters:
//!
//! ```
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
//! let volumes = frame.output.counters.pass("volumes (alpha, z-pass)").expect("a pass");
//! assert!(volumes.samples_passed > 0);
//! # Ok(())
//! # }
//! ```
//!
//! For many frames of one scene (an animation, a moving camera), keep the renderer:
//! `options.technique.build(&gpu, &scene, &options)?` returns a [`SceneRenderer`] whose
//! `frame_with(&moved_scene)` renders a moved pose of the same scene.
//!
//! The pieces, bottom up: [`gpu`] (device under the mobile profile, memory, queries), [`mesh`]
//! (CPU mesh work), [`scene`] (built-in scenes, glTF), [`frame`] and [`pipeline`] (render
//! passes and fixed-function state as data), [`render`] (the recorder that measures passes,
//! pass plans), [`technique`](mod@technique) (every technique behind one interface) and [`profile`] (reports).

// Raw Vulkan lives in gpu/, frame/ and render/, and in layer/ (the fill-rate layer is raw Vulkan
// by nature: it sits between a program and its driver); each unsafe block says why it is sound.
#![warn(clippy::undocumented_unsafe_blocks)]

#[doc(hidden)]
pub mod cli;
pub mod error;
pub mod frame;
pub mod gpu;
pub mod layer;
pub mod mesh;
pub mod names;
pub mod pipeline;
pub mod profile;
pub mod render;
pub mod scene;
pub mod shaders;
pub mod technique;
#[doc(hidden)]
pub mod viewer;

pub use error::{Error, Result};
pub use frame::StencilMode;
pub use gpu::{Gpu, GpuOptions};
pub use render::{FrameCounters, FrameOutput};
pub use scene::{builtin_scene, scene_from_gltf, Scene};
pub use technique::{by_name as technique, render_scene, RenderOptions, SceneRenderer, Technique, TechniqueFrame};
