//! `nostencil bench --technique shadow-texture-atlas`: the paper's Table 1 in one run. Frames
//! per second of shadow textures and the shadow map, moving and fixed light, on both scenes,
//! beside the paper's figures (ATI 9800XT), with the ratios that can be compared across
//! machines: shadow texture / shadow map, and fixed / moving.

use std::fmt::Write as _;
use std::sync::Arc;

use super::bench::{self, BenchSettings, Ratio, Variant, VariantResult};
use super::bootstrap::Bootstrap;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::scene::builtin_scene;
use crate::technique::shadow_atlas::{technique_of, LightMode, ShadowAtlasOptions, ShadowKind};
use crate::technique::RenderOptions;

/// The paper's Table 1 (fps): (scene, technique, moving light, fixed light).
pub const PAPER_TABLE1: [(&str, ShadowKind, f64, f64); 4] = [
    ("atlas-one", ShadowKind::Atlas, 64.53, 127.50),
    ("atlas-one", ShadowKind::Map, 65.58, 127.32),
    ("atlas-125", ShadowKind::Atlas, 12.33, 27.04),
    ("atlas-125", ShadowKind::Map, 13.44, 27.06),
];

/// Timed rounds when `--runs` is not given: the atlas-125 rows take seconds a frame, and the
/// table is read against the paper's figures, not to a few percent.
pub const DEFAULT_RUNS: u32 = 10;

#[derive(Debug, Clone, serde::Serialize)]
pub struct Table1Row {
    pub scene: &'static str,
    pub technique: ShadowKind,
    pub light: LightMode,
    pub fps: f64,
    pub frame_ms: f64,
    pub gpu_ms: f64,
    pub passes: usize,
    pub paper_fps: f64,
    /// The timed frames in round order, ms (every row renders one frame per round).
    pub frame_ms_rounds: Vec<f64>,
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct Table1 {
    pub schema: &'static str,
    pub device: String,
    pub width: u32,
    pub height: u32,
    pub warmup: u32,
    pub runs: u32,
    /// How the intervals of the fps ratios were drawn.
    pub bootstrap: Bootstrap,
    pub rows: Vec<Table1Row>,
}

pub fn bench(gpu: &Arc<Gpu>, options: &RenderOptions, warmup: u32, runs: u32, json: bool) -> Result<()> {
    let scenes = [builtin_scene("atlas-one")?, builtin_scene("atlas-125")?];
    let (width, height) = (options.width, options.height);
    let mut variants = Vec::new();
    let mut keys = Vec::new();
    for scene in &scenes {
        for (name, kind, moving_fps, fixed_fps) in PAPER_TABLE1.iter().filter(|r| r.0 == scene.name) {
            for (light, paper_fps) in [(LightMode::Moving, *moving_fps), (LightMode::Fixed, *fixed_fps)] {
                let technique = technique_of(*kind);
                let opts = RenderOptions {
                    technique,
                    shadow_atlas: ShadowAtlasOptions { light, ..options.shadow_atlas },
                    count_overdraw: false,
                    ..options.clone()
                };
                let mut renderer = technique.build(gpu, scene, &opts)?;
                variants.push(Variant {
                    name: format!("{name} {} {}", kind.name(), light.name()),
                    frame: Box::new(move || Ok(renderer.frame_with(scene)?.output)),
                });
                keys.push((*name, *kind, light, paper_fps));
            }
        }
    }
    let results: Vec<VariantResult> = bench::run(variants, &BenchSettings { warmup, runs, progress: !json })?;
    let rows = keys
        .into_iter()
        .zip(results)
        .map(|((scene, technique, light, paper_fps), r)| Table1Row {
            scene,
            technique,
            light,
            fps: 1000.0 / r.frame_ms.median.max(1e-9),
            frame_ms: r.frame_ms.median,
            gpu_ms: r.gpu_ms.median,
            passes: r.passes,
            paper_fps,
            frame_ms_rounds: r.frame_ms_rounds,
        })
        .collect();
    let table = Table1 {
        schema: "nostencil-table1/2",
        device: gpu.device.info.name.clone(),
        width,
        height,
        warmup,
        runs,
        bootstrap: Bootstrap::DEFAULT,
        rows,
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&table).map_err(|e| Error::Internal(e.to_string()))?);
    } else {
        print!("{}", table.render());
    }
    Ok(())
}

impl Table1 {
    fn row(&self, scene: &str, technique: ShadowKind, light: LightMode) -> Option<&Table1Row> {
        self.rows.iter().find(|r| r.scene == scene && r.technique == technique && r.light == light)
    }

    /// fps of `a` / fps of `b`: in this run as the median of the per-round ratios with its
    /// interval, and in the paper.
    fn fps_ratio(&self, a: &Table1Row, b: &Table1Row) -> (String, f64) {
        let measured = Ratio::per_round(&b.frame_ms_rounds, &a.frame_ms_rounds, &self.bootstrap)
            .map_or("n/a".into(), |r| r.brief());
        (measured, a.paper_fps / b.paper_fps)
    }

    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "Table 1 (seed 004) | {} | {}x{} | {} warm-up + {} timed rounds, one frame of each row per round | paper: ATI 9800XT, shadow map 512x512",
            self.device, self.width, self.height, self.warmup, self.runs
        );
        let _ = writeln!(
            out,
            "{:<10} {:<21} {:<7} {:>7} {:>10} {:>9} {:>7} {:>10}",
            "scene", "technique", "light", "passes", "frame ms", "GPU ms", "fps", "paper fps"
        );
        for r in &self.rows {
            let _ = writeln!(
                out,
                "{:<10} {:<21} {:<7} {:>7} {:>10.2} {:>9.2} {:>7.2} {:>10.2}",
                r.scene,
                r.technique.name(),
                r.light.name(),
                r.passes,
                r.frame_ms,
                r.gpu_ms,
                r.fps,
                r.paper_fps
            );
        }
        let _ = writeln!(
            out,
            "\nratios (this run: median of the per-round ratios [95% bootstrap CI, {} resamples] | paper):",
            self.bootstrap.resamples
        );
        for scene in ["atlas-one", "atlas-125"] {
            for light in [LightMode::Moving, LightMode::Fixed] {
                if let (Some(a), Some(m)) =
                    (self.row(scene, ShadowKind::Atlas, light), self.row(scene, ShadowKind::Map, light))
                {
                    let (measured, paper) = self.fps_ratio(a, m);
                    let _ = writeln!(
                        out,
                        "  {scene:<10} {:<7} shadow texture / shadow map fps: {measured:>17} | {paper:>5.2}",
                        light.name(),
                    );
                }
            }
            for kind in [ShadowKind::Atlas, ShadowKind::Map] {
                if let (Some(f), Some(m)) =
                    (self.row(scene, kind, LightMode::Fixed), self.row(scene, kind, LightMode::Moving))
                {
                    let (measured, paper) = self.fps_ratio(f, m);
                    let _ = writeln!(
                        out,
                        "  {scene:<10} {:<21} fixed / moving fps: {measured:>17} | {paper:>5.2}",
                        kind.name()
                    );
                }
            }
        }
        out
    }
}
