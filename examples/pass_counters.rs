//! Per-pass fill-rate counters of one frame: what each pass of a technique costs.
//!
//!     cargo run --example pass_counters -- [TECHNIQUE] [SCENE]
//!
//! Defaults: `shadow-volume` on the built-in `default` scene at 256x256. Fragments are fragment
//! shader invocations (pipeline statistics), samples are the precise occlusion query's count.

use std::process::ExitCode;

use nostencil::{builtin_scene, render_scene, technique, Gpu, GpuOptions, RenderOptions};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map_or("shadow-volume", String::as_str);
    let scene = args.get(1).map_or("default", String::as_str);
    match run(name, scene) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("pass_counters: {error}");
            ExitCode::FAILURE
        }
    }
}

fn run(name: &str, scene_name: &str) -> nostencil::Result<()> {
    let gpu = Gpu::new(&GpuOptions { validation: None, ..GpuOptions::default() })?;
    let scene = builtin_scene(scene_name)?;
    let options = RenderOptions { technique: technique(name)?, ..RenderOptions::default() };
    let frame = render_scene(&gpu, &scene, &options)?;
    let counters = &frame.output.counters;
    let pixels = f64::from(counters.width * counters.height);
    println!("{name} on '{scene_name}', {}x{}:", counters.width, counters.height);
    println!("{:<40} {:>6} {:>12} {:>10} {:>9} {:>8}", "pass", "draws", "fragments", "samples", "overdraw", "GPU ms");
    for pass in &counters.passes {
        let fragments = pass.fragment_invocations.map_or("-".to_owned(), |f| f.to_string());
        let overdraw = pass.samples_passed as f64 / (pixels * f64::from(counters.samples));
        println!(
            "{:<40} {:>6} {:>12} {:>10} {:>9.3} {:>8.3}",
            pass.name, pass.draws, fragments, pass.samples_passed, overdraw, pass.gpu_ms
        );
    }
    Ok(())
}
