//! The integration tests, in one binary: each file of `tests/` is a module of it, so that
//! `cargo test` links the library once instead of once per file. They use the library's public
//! surface, the `nostencil` program and the fill-rate layer as a user does; the tests that reach
//! inside the crate are compiled into it (`tests/inside/`). `cargo test NAME` filters both (a
//! test's name here is `file::test`); docs/tests.md says what each file proves.
//! Tests that set the process environment run in a process of their own
//! (`common::in_own_process`).

mod common;

mod api_docs;
mod arm_best_practices;
mod colour;
mod examples;
mod fillrate_layer;
mod fillrate_layer_boundary;
mod fillrate_layer_draws;
mod fillrate_layer_resubmit;
mod fillrate_layer_timeline;
mod fillrate_layer_unhandled;
mod fillrate_layer_work;
mod html_report;
mod layering;
mod profile_app;
mod profile_app_gl;
mod profile_app_work;
mod readme;
mod real_programs;
mod samples;
mod standalone;
mod tiler_check;
