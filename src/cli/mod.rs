//! The command line, thin over the library: parse, build the scene, run, report.

mod app_counts;
mod args;
mod bench;
mod commands;
mod frame_loop;
mod frame_setup;
mod install;
mod output_path;
mod profile_app;
mod profile_frame;
mod supervise;

use std::process::ExitCode;

use clap::Parser;

use args::Cli;

/// Runs the CLI and maps every failure to a one-line message and a non-zero exit code.
pub fn main() -> ExitCode {
    end_quietly_on_a_closed_pipe();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                let _ = e.print();
                return if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
                    ExitCode::from(2)
                } else {
                    ExitCode::SUCCESS
                };
            }
            // clap's first line says what is wrong; usage follows in `--help`.
            let rendered = e.render().to_string();
            let mut first = rendered.lines().next().unwrap_or("error: invalid arguments").to_owned();
            // A first line ending in ':' lists what it means on the indented lines after it
            // (the required arguments not given): they join it.
            if first.ends_with(':') {
                let listed: Vec<&str> = rendered
                    .lines()
                    .skip(1)
                    .take_while(|l| l.starts_with(' ') && !l.trim().is_empty())
                    .map(str::trim)
                    .collect();
                first = format!("{first} {}", listed.join(", "));
            }
            // A value-enum option's choices stay on the one line.
            let choices = rendered.lines().map(str::trim).find(|l| l.starts_with("[possible values:"));
            match choices {
                Some(choices) => eprintln!("nostencil: {first} {choices} (see nostencil --help)"),
                None => eprintln!("nostencil: {first} (see nostencil --help)"),
            }
            return ExitCode::from(2);
        }
    };
    match commands::run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("nostencil: error: {e}");
            ExitCode::from(1)
        }
    }
}

/// `nostencil info | head -1`: once the reader is gone the process ends quietly, as any Unix
/// filter does, instead of the next print panicking (Rust starts programs with SIGPIPE ignored).
fn end_quietly_on_a_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: restores the default action of one signal, before any thread of ours exists; no
    // handler of ours is replaced.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}
