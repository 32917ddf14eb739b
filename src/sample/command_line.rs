//! A sample's `main`: its two options (`--out FILE.png`, `--stencil`), the device, and the frame
//! written as a PNG, with a one-line error naming the problem and exit code 1 (2 for a bad
//! argument). The same for every sample, so it lives here, as Sascha Willems' `VULKAN_EXAMPLE_MAIN`.

use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;

use image::RgbaImage;

use crate::error::Result;
use crate::frame::write_png;
use crate::gpu::{Gpu, GpuOptions};

/// Runs the sample `name`: `render(gpu, stencil)` draws its frame, with a real stencil when
/// `--stencil` is given, and the frame goes to `--out` (default `NAME.png`).
pub fn run(name: &str, render: impl FnOnce(&Arc<Gpu>, bool) -> Result<RgbaImage>) -> ExitCode {
    let (out, stencil) = match parse(name, std::env::args().skip(1)) {
        Ok(options) => options,
        Err(problem) => {
            eprintln!("{name}: {problem}\nusage: {name} [--out FILE.png] [--stencil]");
            return ExitCode::from(2);
        }
    };
    let result = Gpu::new(&GpuOptions::default())
        .and_then(|gpu| render(&gpu, stencil))
        .and_then(|frame| write_png(&frame, Path::new(&out), false));
    match result {
        Ok(()) => {
            println!("wrote {out}");
            ExitCode::SUCCESS
        }
        Err(error) => {
            eprintln!("{name}: {error}");
            ExitCode::FAILURE
        }
    }
}

/// The output file and whether to use a real stencil, or what is wrong with the arguments.
fn parse(name: &str, mut args: impl Iterator<Item = String>) -> std::result::Result<(String, bool), String> {
    let (mut out, mut stencil) = (format!("{name}.png"), false);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--stencil" => stencil = true,
            "--out" => out = args.next().ok_or("--out needs a file name")?,
            other => return Err(format!("unknown argument '{other}'")),
        }
    }
    Ok((out, stencil))
}

#[cfg(test)]
mod tests {
    use super::parse;

    fn args(list: &[&str]) -> impl Iterator<Item = String> {
        list.iter().map(|s| s.to_string()).collect::<Vec<_>>().into_iter()
    }

    #[test]
    fn the_two_options_and_what_is_wrong_with_anything_else() {
        assert_eq!(parse("outline", args(&[])), Ok(("outline.png".into(), false)));
        assert_eq!(parse("outline", args(&["--stencil", "--out", "a.png"])), Ok(("a.png".into(), true)));
        assert_eq!(parse("outline", args(&["--out"])), Err("--out needs a file name".into()));
        assert_eq!(parse("outline", args(&["--size", "4"])), Err("unknown argument '--size'".into()));
    }
}
