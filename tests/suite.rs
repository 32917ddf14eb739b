//! Every integration test, in one binary: each file of `tests/` is a module of it, so that
//! `cargo test` links the library once instead of once per file. `cargo test NAME` filters as
//! before (a test's name is now `file::test`); docs/tests.md says what each file proves.
//! Tests that set the process environment run in a process of their own
//! (`common::in_own_process`).

mod common;

mod atlas_page;
mod cartoon;
mod cartoon_cli;
mod cli;
mod colour;
mod counters;
mod examples;
mod fillrate_layer;
mod fillrate_layer_boundary;
mod fillrate_layer_resubmit;
mod fillrate_layer_timeline;
mod fillrate_layer_unhandled;
mod fillrate_layer_work;
mod frame;
mod fuzz_gltf;
mod gltf_conformance;
mod gpu_faults;
mod ink_methods;
mod layering;
mod lights;
mod maps_per_light;
mod materials;
mod msaa_samples;
mod outline_methods;
mod plan;
mod planar;
mod profile;
mod profile_app;
mod profile_app_work;
mod readme;
mod real_programs;
mod shadow_atlas;
mod shadow_volume;
mod shadow_volume_gltf;
mod standalone;
mod sync_canary;
mod tiler_check;
mod viewer;
mod xray;
