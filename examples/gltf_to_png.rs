//! A glTF file to a PNG, with one of nostencil's techniques: what a port does first.
//!
//!     cargo run --example gltf_to_png -- tests/assets/BoxAnimated.glb box.png [TECHNIQUE]
//!
//! TECHNIQUE defaults to `shadow-volume` (`nostencil info` lists them all). The frame is
//! 320x240, stencil-free; add `--stencil reference` to the CLI for the real-stencil version.

use std::path::PathBuf;
use std::process::ExitCode;

use nostencil::{
    render_scene, scene_and_warnings_from_gltf, technique, write_png, Gpu, GpuOptions, RenderOptions, StencilMode,
};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(input), Some(output)) = (args.first(), args.get(1)) else {
        eprintln!("usage: gltf_to_png FILE.gltf|FILE.glb OUT.png [TECHNIQUE]");
        return ExitCode::from(2);
    };
    let name = args.get(2).map_or("shadow-volume", String::as_str);
    match run(PathBuf::from(input), PathBuf::from(output), name) {
        Ok(summary) => {
            println!("{summary}");
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("gltf_to_png: {error}");
            ExitCode::FAILURE
        }
    }
}

fn run(input: PathBuf, output: PathBuf, name: &str) -> nostencil::Result<String> {
    // Validation off: an example runs like an application would.
    let gpu = Gpu::new(&GpuOptions { validation: None, ..GpuOptions::default() })?;
    // The scene at animation time 0, framed by its own camera (or one fitted to it); what the
    // file holds that nostencil cannot honour is named, never dropped silently.
    let (scene, loader_warnings) = scene_and_warnings_from_gltf(&input, 0.0)?;
    for warning in &loader_warnings {
        eprintln!("warning: {warning}");
    }
    let options = RenderOptions {
        width: 320,
        height: 240,
        technique: technique(name)?,
        stencil: StencilMode::Emulated,
        ..RenderOptions::default()
    };
    let frame = render_scene(&gpu, &scene, &options)?;
    for warning in &frame.warnings {
        eprintln!("warning: {warning}");
    }
    write_png(&frame.output.image, &output, false)?;
    Ok(format!("wrote {} ({name}, {} passes)", output.display(), frame.output.counters.passes.len()))
}
