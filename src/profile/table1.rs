//! `nostencil bench --technique shadow-texture-atlas`: the paper's Table 1 in one run. Frames
//! per second of shadow textures and the shadow map, moving and fixed light, on both scenes,
//! beside the paper's figures (ATI 9800XT), with the ratios that can be compared across
//! machines: shadow texture / shadow map, and fixed / moving.

use std::fmt::Write as _;
use std::sync::Arc;

use super::bench::{self, BenchSettings, Variant, VariantResult};
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
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct Table1 {
    pub schema: &'static str,
    pub device: String,
    pub width: u32,
    pub height: u32,
    pub warmup: u32,
    pub runs: u32,
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
        })
        .collect();
    let table = Table1 {
        schema: "nostencil-table1/1",
        device: gpu.device.info.name.clone(),
        width,
        height,
        warmup,
        runs,
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
    fn fps(&self, scene: &str, technique: ShadowKind, light: LightMode) -> Option<(f64, f64)> {
        self.rows
            .iter()
            .find(|r| r.scene == scene && r.technique == technique && r.light == light)
            .map(|r| (r.fps, r.paper_fps))
    }

    pub fn render(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "Table 1 (seed 004) | {} | {}x{} | {} warm-up + {} runs per row | paper: ATI 9800XT, shadow map 512x512",
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
        let _ = writeln!(out, "\nratios (this run | paper):");
        for scene in ["atlas-one", "atlas-125"] {
            for light in [LightMode::Moving, LightMode::Fixed] {
                if let (Some(a), Some(m)) =
                    (self.fps(scene, ShadowKind::Atlas, light), self.fps(scene, ShadowKind::Map, light))
                {
                    let _ = writeln!(
                        out,
                        "  {scene:<10} {:<7} shadow texture / shadow map fps: {:>5.2} | {:>5.2}",
                        light.name(),
                        a.0 / m.0,
                        a.1 / m.1
                    );
                }
            }
            for kind in [ShadowKind::Atlas, ShadowKind::Map] {
                if let (Some(f), Some(m)) =
                    (self.fps(scene, kind, LightMode::Fixed), self.fps(scene, kind, LightMode::Moving))
                {
                    let _ = writeln!(
                        out,
                        "  {scene:<10} {:<21} fixed / moving fps: {:>5.2} | {:>5.2}",
                        kind.name(),
                        f.0 / m.0,
                        f.1 / m.1
                    );
                }
            }
        }
        out
    }
}
