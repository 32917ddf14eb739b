//! `nostencil bench --loop N`: each technique of `--technique` (one, a list, or `all`) plays N
//! frames of the scene animated as the viewer animates it (glTF animations play, shadow casters
//! turn), its frames kept on the GPU as a game's are; the techniques take turns, a frame each.
//! Reports throughput, the render thread's CPU time a frame, and the allocations and waits a
//! frame makes (`profile::frame_loop`).

use super::args::FrameArgs;
use super::frame_setup::{load_scene, open_gpu, options, print_warnings};
use crate::error::{Error, Result};
use crate::profile::frame_loop::{self, LoopReport, LoopVariant};
use crate::technique::{by_name, SceneRenderer, TECHNIQUES};
use crate::viewer::controls::Live;

/// The loop's clock: a frame every sixtieth of a second of animation.
const FRAME_SECONDS: f32 = 1.0 / 60.0;

pub(super) fn bench_loop(frame: &FrameArgs, frames: u32, warmup: u32, json: bool) -> Result<()> {
    if frames == 0 {
        return Err(Error::InvalidInput("--loop takes the number of frames to play, at least 1".into()));
    }
    let names: Vec<String> = if frame.technique == "all" {
        TECHNIQUES.iter().map(|t| t.name().to_owned()).collect()
    } else {
        let names: Vec<String> = frame.technique.split(',').map(|n| n.trim().to_owned()).collect();
        for (index, name) in names.iter().enumerate() {
            if name.is_empty() || name == "all" || names[..index].contains(name) {
                return Err(Error::InvalidInput(format!(
                    "--technique {}: a list names each technique once, without `all` (e.g. shadow-volume,lit)",
                    frame.technique
                )));
            }
            by_name(name)?;
        }
        names
    };
    let mut listed = Vec::new();
    for name in &names {
        listed.push((name.clone(), options(&FrameArgs { technique: name.clone(), ..frame.clone() })?));
    }
    let base = load_scene(frame)?;
    let gpu = open_gpu(&frame.gpu)?;
    let mut variants = Vec::new();
    for (name, options) in &listed {
        let mut renderer: SceneRenderer<'_> = options.technique.build(&gpu, &base, options)?;
        print_warnings(options.technique.name(), renderer.warnings());
        // A game's frame stays on the GPU: no read-back.
        renderer.renderer_mut().keep_on_gpu(true);
        let mut live = Live::new(&base, false, frame.time);
        let mut scene = live.lit(&base);
        let base = &base;
        variants.push(LoopVariant {
            name: name.clone(),
            frame: Box::new(move |index| {
                live.time = index as f32 * FRAME_SECONDS;
                live.apply(base, &mut scene)?;
                renderer.frame_with(&scene).map(|_| ())
            }),
        });
    }
    let measured = frame_loop::play(&gpu, &mut variants, warmup, frames)?;
    let (width, height) = listed.first().map_or((0, 0), |(_, o)| (o.width, o.height));
    let report = LoopReport {
        device: gpu.device.info.name.clone(),
        scene: base.name.clone(),
        width,
        height,
        samples: frame.samples,
        warmup,
        results: frame_loop::summarise(&names, &measured),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&report).map_err(|e| Error::Internal(e.to_string()))?);
    } else {
        print!("{}", report.table());
    }
    Ok(())
}
