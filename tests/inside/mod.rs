//! The tests that reach inside the crate: compiled into the library's own test build (see
//! `src/lib.rs`), where every module is visible and `nostencil::` names the crate itself.
//! docs/tests.md says what each file proves. `cargo test NAME` filters them as it does the
//! integration suite (`tests/suite.rs`); a test's name here is `inside::file::test`.

mod atlas_page;
mod cartoon;
mod cartoon_cli;
mod cli;
mod counters;
#[cfg(feature = "cpu-bench")]
mod cpu_bench;
mod frame;
mod frames_in_flight;
mod fuzz_gltf;
mod gltf_conformance;
mod gpu_faults;
mod gpu_skinning;
mod ink_methods;
mod lights;
mod maps_per_light;
mod materials;
mod mirrored;
mod msaa_samples;
mod outline_methods;
mod plan;
mod planar;
mod profile;
mod shadow_atlas;
mod shadow_volume;
mod shadow_volume_gltf;
mod sync_canary;
mod viewer;
mod xray;
