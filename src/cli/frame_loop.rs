//! `nostencil bench --loop N`: each technique of `--technique` (one, a list, or `all`) plays N
//! frames of the scene animated as the viewer animates it (glTF animations play, shadow casters
//! turn), its frames kept on the GPU as a game's are; the techniques take turns, a frame each.
//! Reports throughput, the render thread's CPU time a frame, and the allocations and waits a
//! frame makes (`profile::frame_loop`).

use super::args::FrameArgs;
use super::frame_setup::{load_scene, open_gpu, options, print_warnings};
use crate::error::{Error, Result};
use crate::profile::frame_loop::{self, LoopReport, LoopVariant};
use crate::render::Skinning;
use crate::technique::{by_name, RenderOptions, SceneRenderer, ShadowVolumeOptions, VolumeExtrusion, TECHNIQUES};
use crate::viewer::controls::Live;

/// The loop's clock: a frame every sixtieth of a second of animation.
const FRAME_SECONDS: f32 = 1.0 / 60.0;

/// Frames a technique plays in a turn when it keeps several in flight.
const TURN_FRAMES: u32 = 8;

/// How the loop plays: N frames a technique, after `warmup` turns, `in_flight` frames in
/// flight, shadow-volume once per volume extrusion with `each_extrusion`, and each technique
/// once per skinning with `each_skinning`.
pub(super) struct Playing {
    pub frames: u32,
    pub in_flight: u32,
    pub warmup: u32,
    pub each_extrusion: bool,
    pub each_skinning: bool,
}

pub(super) fn bench_loop(frame: &FrameArgs, playing: Playing, json: bool) -> Result<()> {
    let Playing { frames, in_flight, warmup, each_extrusion, each_skinning } = playing;
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
        let options = options(&FrameArgs { technique: name.clone(), ..frame.clone() })?;
        let options = RenderOptions { frames_in_flight: in_flight, ..options };
        if each_extrusion && name == "shadow-volume" {
            for extrusion in VolumeExtrusion::ALL {
                let shadow_volume = ShadowVolumeOptions { extrusion: *extrusion, ..options.shadow_volume };
                let named = format!("{name} ({})", extrusion.name());
                listed.push((named, RenderOptions { shadow_volume, ..options.clone() }));
            }
        } else {
            listed.push((name.clone(), options));
        }
    }
    if each_skinning {
        listed = listed
            .into_iter()
            .flat_map(|(name, options)| {
                Skinning::ALL.iter().map(move |skinning| {
                    (format!("{name} ({skinning} skinning)"), RenderOptions { skinning: *skinning, ..options.clone() })
                })
            })
            .collect();
    }
    let names: Vec<String> = listed.iter().map(|(name, _)| name.clone()).collect();
    let turn = if in_flight > 1 { TURN_FRAMES } else { 1 };
    let base = load_scene(frame)?;
    let gpu = open_gpu(&frame.gpu)?;
    let mut variants = Vec::new();
    let mut kept_in_flight = Vec::new();
    for (_, options) in &listed {
        let renderer: SceneRenderer<'_> = options.technique.build(&gpu, &base, options)?;
        print_warnings(options.technique.name(), renderer.warnings());
        // Shared by the frame and the end of the turn.
        let renderer = std::rc::Rc::new(std::cell::RefCell::new(renderer));
        // A game's frame stays on the GPU: no read-back.
        renderer.borrow_mut().keep_on_gpu(true);
        let in_flight = renderer.borrow_mut().frames_in_flight();
        kept_in_flight.push((in_flight, renderer.borrow().skinning()));
        let mut live = Live::new(&base, false, frame.time);
        let mut scene = live.lit(&base);
        let base = &base;
        let finishing = renderer.clone();
        variants.push(LoopVariant {
            frame: Box::new(move |index| {
                live.time = index as f32 * FRAME_SECONDS;
                live.apply(base, &mut scene)?;
                renderer.borrow_mut().frame_with(&scene).map(|_| ())
            }),
            finish: Box::new(move || finishing.borrow_mut().wait_all()),
        });
    }
    let measured = frame_loop::play(&gpu, &mut variants, warmup, frames, turn)?;
    let (width, height) = listed.first().map_or((0, 0), |(_, o)| (o.width, o.height));
    let report = LoopReport {
        device: gpu.device.info.name.clone(),
        scene: base.name.clone(),
        width,
        height,
        samples: frame.samples,
        warmup,
        turn,
        results: frame_loop::summarise(&names, &kept_in_flight, &measured),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&report).map_err(|e| Error::Internal(e.to_string()))?);
    } else {
        print!("{}", report.table());
    }
    Ok(())
}
