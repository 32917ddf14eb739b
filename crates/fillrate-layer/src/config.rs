//! The layer's settings, read from the environment at vkCreateInstance.

use std::path::PathBuf;

pub use nostencil_fillrate_report::output::OutputFormat;

/// What ends a frame when the program does not mark frames with VK_EXT_frame_boundary.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum FrameOn {
    /// vkQueuePresentKHR (the default).
    #[default]
    Present,
    /// Every vkQueueSubmit / vkQueueSubmit2 call.
    Submit,
    /// Every successful host wait: a fence, a timeline semaphore, a queue or the device idle.
    Wait,
    /// Every buffer swap of a GL or GLES program (`glXSwapBuffers`, `eglSwapBuffers`), seen by
    /// `libnostencil_gl_swaps.so` preloaded into the program (gl_swaps.rs; `profile-app --gl`).
    Swap,
}

impl FrameOn {
    pub fn parse(text: &str) -> Option<Self> {
        match text {
            "present" => Some(FrameOn::Present),
            "submit" => Some(FrameOn::Submit),
            "wait" => Some(FrameOn::Wait),
            "swap" => Some(FrameOn::Swap),
            _ => None,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Config {
    /// `NOSTENCIL_FILLRATE_OUT`: without it the layer measures nothing.
    pub out: Option<PathBuf>,
    /// `NOSTENCIL_FILLRATE_FORMAT`: json (default), csv or table.
    pub format: OutputFormat,
    /// `NOSTENCIL_FILLRATE_FRAMES`: measure the first N frames only.
    pub frames: Option<u64>,
    /// `NOSTENCIL_FILLRATE_PER_DRAW=1`: also count each draw of a measured pass on its own.
    pub per_draw: bool,
    /// `NOSTENCIL_FILLRATE_TILER=1`: the tiler check (tiler_check.rs): poison what a tiler
    /// would not keep and flag the load/store mistakes.
    pub tiler: bool,
    /// `NOSTENCIL_FILLRATE_EVERY`: also rewrite the file every K frames, at most every 100 ms,
    /// and append each finished frame to the journal beside it (report.rs, `JournalLine`)
    /// (0: never).
    pub every: u64,
    /// `NOSTENCIL_FILLRATE_CAPTURE` (and `_CAPTURE_FRAME`): write the image presented at the
    /// end of one frame as a PNG (capture.rs).
    pub capture: Option<CaptureConfig>,
    /// `NOSTENCIL_FILLRATE_FRAME_ON`: present (default), submit or wait.
    pub frame_on: FrameOn,
}

/// Where and when to capture a presented image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CaptureConfig {
    pub path: PathBuf,
    /// The frame whose present is captured, from 0 (the report's frame index).
    pub frame: u64,
}

impl Config {
    pub fn from_env() -> (Self, Vec<String>) {
        Self::parse(|name| std::env::var(name).ok())
    }

    /// The settings from `var`, and a warning per value that could not be used (named, with
    /// what was used instead).
    pub fn parse(var: impl Fn(&str) -> Option<String>) -> (Self, Vec<String>) {
        let mut warnings = Vec::new();
        let out = var("NOSTENCIL_FILLRATE_OUT").filter(|p| !p.is_empty()).map(PathBuf::from);
        let format = match var("NOSTENCIL_FILLRATE_FORMAT").as_deref() {
            None | Some("") | Some("json") => OutputFormat::Json,
            Some("csv") => OutputFormat::Csv,
            Some("table") => OutputFormat::Table,
            Some(other) => {
                warnings.push(format!("NOSTENCIL_FILLRATE_FORMAT='{other}' is not json, csv or table; writing json"));
                OutputFormat::Json
            }
        };
        let mut number = |name: &str| match var(name).filter(|v| !v.is_empty()) {
            None => None,
            Some(text) => match text.trim().parse::<u64>() {
                Ok(n) => Some(n),
                Err(_) => {
                    warnings.push(format!("{name}='{text}' is not a whole number; ignored"));
                    None
                }
            },
        };
        let frames = number("NOSTENCIL_FILLRATE_FRAMES");
        let every = number("NOSTENCIL_FILLRATE_EVERY").unwrap_or(0);
        let capture_frame = number("NOSTENCIL_FILLRATE_CAPTURE_FRAME");
        let frames = match frames {
            Some(0) => {
                warnings.push("NOSTENCIL_FILLRATE_FRAMES=0 measures nothing; measuring every frame".into());
                None
            }
            other => other,
        };
        let per_draw = var("NOSTENCIL_FILLRATE_PER_DRAW").is_some_and(|v| v == "1");
        let tiler = var("NOSTENCIL_FILLRATE_TILER").is_some_and(|v| v == "1");
        let capture = var("NOSTENCIL_FILLRATE_CAPTURE").filter(|p| !p.is_empty()).map(PathBuf::from);
        if capture.is_none() && capture_frame.is_some() {
            warnings
                .push("NOSTENCIL_FILLRATE_CAPTURE_FRAME without NOSTENCIL_FILLRATE_CAPTURE: nothing captured".into());
        }
        let capture = capture.map(|path| CaptureConfig { path, frame: capture_frame.unwrap_or(0) });
        let frame_on = match var("NOSTENCIL_FILLRATE_FRAME_ON").filter(|v| !v.is_empty()) {
            None => FrameOn::Present,
            Some(text) => FrameOn::parse(&text).unwrap_or_else(|| {
                warnings.push(format!(
                    "NOSTENCIL_FILLRATE_FRAME_ON='{text}' is not present, submit, wait or swap; using present"
                ));
                FrameOn::Present
            }),
        };
        (Config { out, format, frames, every, per_draw, tiler, capture, frame_on }, warnings)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(vars: &[(&str, &str)]) -> (Config, Vec<String>) {
        Config::parse(|name| vars.iter().find(|(n, _)| *n == name).map(|(_, v)| v.to_string()))
    }

    #[test]
    fn defaults_and_values_and_named_warnings() {
        let (config, warnings) = parse(&[]);
        assert_eq!(
            config,
            Config {
                out: None,
                format: OutputFormat::Json,
                frames: None,
                every: 0,
                per_draw: false,
                tiler: false,
                capture: None,
                frame_on: FrameOn::Present,
            }
        );
        assert!(parse(&[("NOSTENCIL_FILLRATE_TILER", "1")]).0.tiler);
        assert!(warnings.is_empty());
        assert_eq!(parse(&[("NOSTENCIL_FILLRATE_FRAME_ON", "submit")]).0.frame_on, FrameOn::Submit);
        assert_eq!(parse(&[("NOSTENCIL_FILLRATE_FRAME_ON", "swap")]).0.frame_on, FrameOn::Swap);
        let (config, warnings) = parse(&[("NOSTENCIL_FILLRATE_FRAME_ON", "fence")]);
        assert!(config.frame_on == FrameOn::Present && warnings[0].contains("fence"), "{warnings:?}");
        let (config, _) = parse(&[
            ("NOSTENCIL_FILLRATE_OUT", "/tmp/x.json"),
            ("NOSTENCIL_FILLRATE_FORMAT", "csv"),
            ("NOSTENCIL_FILLRATE_FRAMES", "5"),
            ("NOSTENCIL_FILLRATE_EVERY", "2"),
        ]);
        assert_eq!(config.out.as_deref(), Some(std::path::Path::new("/tmp/x.json")));
        assert_eq!((config.format, config.frames, config.every), (OutputFormat::Csv, Some(5), 2));
        let (config, warnings) = parse(&[("NOSTENCIL_FILLRATE_FORMAT", "xml"), ("NOSTENCIL_FILLRATE_FRAMES", "ten")]);
        assert_eq!((config.format, config.frames), (OutputFormat::Json, None));
        assert_eq!(warnings.len(), 2);
        assert!(warnings[0].contains("xml") && warnings[1].contains("NOSTENCIL_FILLRATE_FRAMES"));
        let (config, warnings) =
            parse(&[("NOSTENCIL_FILLRATE_CAPTURE", "/tmp/f.png"), ("NOSTENCIL_FILLRATE_CAPTURE_FRAME", "4")]);
        let frame_4 = CaptureConfig { path: "/tmp/f.png".into(), frame: 4 };
        assert_eq!((config.capture, warnings.len()), (Some(frame_4), 0));
        assert_eq!(parse(&[("NOSTENCIL_FILLRATE_CAPTURE", "/tmp/f.png")]).0.capture.map(|c| c.frame), Some(0));
        let (config, warnings) = parse(&[("NOSTENCIL_FILLRATE_CAPTURE_FRAME", "4")]);
        assert!(config.capture.is_none() && warnings[0].contains("without NOSTENCIL_FILLRATE_CAPTURE"), "{warnings:?}");
    }
}
