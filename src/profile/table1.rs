//! `nostencil bench --technique shadow-texture-atlas`: the paper's Table 1 in one run. Frames
//! per second of shadow textures and the shadow map, moving and fixed light, on both scenes,
//! beside the paper's figures (ATI 9800XT), with the ratios that can be compared across
//! machines: shadow texture / shadow map, and fixed / moving.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::bench::{self, BenchSettings, Ratio, Variant, VariantResult};
use super::bootstrap::Bootstrap;
use crate::error::{Error, Result};
use crate::gpu::Gpu;
use crate::scene::builtin_scene;
use crate::technique::options::{LightMode, ShadowAtlasOptions, ShadowKind};
use crate::technique::{RenderOptions, Technique};

/// The paper's Table 1 (fps): (scene, technique, moving light, fixed light).
pub const PAPER_TABLE1: [(&str, ShadowKind, f64, f64); 4] = [
    ("atlas-one", ShadowKind::Atlas, 64.53, 127.50),
    ("atlas-one", ShadowKind::Map, 65.58, 127.32),
    ("atlas-125", ShadowKind::Atlas, 12.33, 27.04),
    ("atlas-125", ShadowKind::Map, 13.44, 27.06),
];

/// The techniques Table 1 compares (and the mip-flicker measure with it): `bench` with one of
/// them prints the table in place of timing the technique's variants.
pub const TECHNIQUES: [ShadowKind; 2] = [ShadowKind::Atlas, ShadowKind::Map];

/// Whether `bench --technique` with `technique` reproduces Table 1.
pub fn covers(technique: Technique) -> bool {
    TECHNIQUES.iter().any(|kind| kind.technique() == technique)
}

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
    /// The ratios that can be compared across machines, with the paper's.
    pub ratios: Vec<Table1Ratio>,
}

/// One ratio of Table 1: fps of `numerator` / fps of `denominator` on one scene, measured in this
/// run (median of the per-round ratios, with its interval) and in the paper.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Table1Ratio {
    pub scene: &'static str,
    /// What is compared, e.g. "shadow texture / shadow map fps, moving light".
    pub compared: String,
    /// `None` when no round could be compared.
    pub measured: Option<Ratio>,
    pub paper: f64,
}

/// Runs Table 1 (both scenes, both techniques, moving and fixed light) and returns it.
pub fn run(gpu: &Arc<Gpu>, options: &RenderOptions, warmup: u32, runs: u32, progress: bool) -> Result<Table1> {
    let scenes = [builtin_scene("atlas-one")?, builtin_scene("atlas-125")?];
    let (width, height) = (options.width, options.height);
    let mut variants = Vec::new();
    let mut keys = Vec::new();
    for scene in &scenes {
        for (name, kind, moving_fps, fixed_fps) in PAPER_TABLE1.iter().filter(|r| r.0 == scene.name) {
            for (light, paper_fps) in [(LightMode::Moving, *moving_fps), (LightMode::Fixed, *fixed_fps)] {
                let technique = kind.technique();
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
    let results: Vec<VariantResult> = bench::run(variants, &BenchSettings { warmup, runs, progress })?;
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
    let mut table = Table1 {
        schema: "nostencil-table1/3",
        device: gpu.device.info.name.clone(),
        width,
        height,
        warmup,
        runs,
        bootstrap: Bootstrap::DEFAULT,
        rows,
        ratios: Vec::new(),
    };
    table.ratios = table.compute_ratios();
    Ok(table)
}

/// `bench --technique shadow-texture-atlas`: Table 1 printed (as text or JSON) and, with
/// `out`, recorded there as `table1.json` and `table1.md`.
pub fn bench(
    gpu: &Arc<Gpu>,
    options: &RenderOptions,
    warmup: u32,
    runs: u32,
    json: bool,
    out: Option<&Path>,
) -> Result<()> {
    let table = run(gpu, options, warmup, runs, !json)?;
    if json {
        println!("{}", table.json()?);
    } else {
        print!("{}", table.render());
    }
    if let Some(dir) = out {
        let written = table.write(dir)?;
        eprintln!(
            "Table 1 recorded: {}",
            written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
        );
    }
    Ok(())
}

/// The rows' column titles, in both renderings.
const ROW_COLUMNS: [&str; 8] = ["scene", "technique", "light", "passes", "frame ms", "GPU ms", "fps", "paper fps"];

impl Table1 {
    fn row(&self, scene: &str, technique: ShadowKind, light: LightMode) -> Option<&Table1Row> {
        self.rows.iter().find(|r| r.scene == scene && r.technique == technique && r.light == light)
    }

    /// fps of `a` / fps of `b` on `scene`: in this run as the median of the per-round ratios
    /// with its interval, and in the paper.
    fn fps_ratio(&self, scene: &'static str, compared: String, a: &Table1Row, b: &Table1Row) -> Table1Ratio {
        Table1Ratio {
            scene,
            compared,
            measured: Ratio::per_round(&b.frame_ms_rounds, &a.frame_ms_rounds, &self.bootstrap),
            paper: a.paper_fps / b.paper_fps,
        }
    }

    /// The ratios that can be compared across machines: shadow texture / shadow map per light,
    /// fixed / moving per technique, on each scene.
    fn compute_ratios(&self) -> Vec<Table1Ratio> {
        let mut ratios = Vec::new();
        for scene in ["atlas-one", "atlas-125"] {
            for light in [LightMode::Moving, LightMode::Fixed] {
                if let (Some(a), Some(m)) =
                    (self.row(scene, ShadowKind::Atlas, light), self.row(scene, ShadowKind::Map, light))
                {
                    let compared = format!("shadow texture / shadow map fps, {} light", light.name());
                    ratios.push(self.fps_ratio(scene, compared, a, m));
                }
            }
            for kind in TECHNIQUES {
                if let (Some(f), Some(m)) =
                    (self.row(scene, kind, LightMode::Fixed), self.row(scene, kind, LightMode::Moving))
                {
                    ratios.push(self.fps_ratio(scene, format!("{} fixed / moving fps", kind.name()), f, m));
                }
            }
        }
        ratios
    }

    fn header(&self) -> String {
        format!(
            "Table 1 (seed 004) | {} | {}x{} | {} warm-up + {} timed rounds, one frame of each row per round | paper: ATI 9800XT, shadow map 512x512",
            self.device, self.width, self.height, self.warmup, self.runs
        )
    }

    /// A row's cells, in the order of [`ROW_COLUMNS`]: both renderings show exactly these.
    fn row_cells(r: &Table1Row) -> [String; 8] {
        [
            r.scene.to_string(),
            r.technique.name().to_string(),
            r.light.name().to_string(),
            r.passes.to_string(),
            format!("{:.2}", r.frame_ms),
            format!("{:.2}", r.gpu_ms),
            format!("{:.2}", r.fps),
            format!("{:.2}", r.paper_fps),
        ]
    }

    /// A ratio's cells: scene, what is compared, this run's median [CI], the paper's.
    fn ratio_cells(ratio: &Table1Ratio) -> [String; 4] {
        [
            ratio.scene.to_string(),
            ratio.compared.to_string(),
            ratio.measured.as_ref().map_or("n/a".into(), Ratio::brief),
            format!("{:.2}", ratio.paper),
        ]
    }

    pub fn json(&self) -> Result<String> {
        serde_json::to_string_pretty(self).map_err(|e| Error::Internal(e.to_string()))
    }

    pub fn render(&self) -> String {
        // Column widths; the first three columns are left-aligned, the rest right-aligned.
        const ROW_WIDTHS: [usize; 8] = [10, 21, 7, 7, 10, 9, 7, 10];
        let line = |cells: &[String]| {
            let padded: Vec<String> = cells
                .iter()
                .zip(ROW_WIDTHS)
                .enumerate()
                .map(|(i, (cell, width))| if i < 3 { format!("{cell:<width$}") } else { format!("{cell:>width$}") })
                .collect();
            padded.join(" ")
        };
        let mut out = String::new();
        let _ = writeln!(out, "{}", self.header());
        let _ = writeln!(out, "{}", line(&ROW_COLUMNS.map(str::to_owned)));
        for r in &self.rows {
            let _ = writeln!(out, "{}", line(&Self::row_cells(r)));
        }
        let _ = writeln!(
            out,
            "\nratios (this run: median of the per-round ratios [95% bootstrap CI, {} resamples] | paper):",
            self.bootstrap.resamples
        );
        for ratio in &self.ratios {
            let [scene, compared, measured, paper] = Self::ratio_cells(ratio);
            let _ = writeln!(out, "  {scene:<10} {compared:<52} {measured:>17} | {paper:>5}");
        }
        out
    }

    /// The same table as Markdown: the rows beside the paper's fps, then the ratios.
    pub fn markdown(&self) -> String {
        let row = |cells: &[String]| format!("| {} |", cells.join(" | "));
        let mut out = String::new();
        let _ = writeln!(out, "{}\n", self.header());
        let _ = writeln!(out, "{}", row(&ROW_COLUMNS.map(str::to_owned)));
        let _ = writeln!(out, "|---|---|---|---:|---:|---:|---:|---:|");
        for r in &self.rows {
            let _ = writeln!(out, "{}", row(&Self::row_cells(r)));
        }
        let _ = writeln!(
            out,
            "\nRatios: this run's median of the per-round ratios [95% bootstrap interval, {} resamples], and the paper's.\n",
            self.bootstrap.resamples
        );
        let _ = writeln!(out, "| scene | ratio | this run | paper |");
        let _ = writeln!(out, "|---|---|---:|---:|");
        for ratio in &self.ratios {
            let _ = writeln!(out, "{}", row(&Self::ratio_cells(ratio)));
        }
        out
    }

    /// Writes `table1.json` and `table1.md` into `dir` (created if missing), each atomically;
    /// returns their paths.
    pub fn write(&self, dir: &Path) -> Result<[PathBuf; 2]> {
        std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.to_owned(), source })?;
        let json = dir.join("table1.json");
        let markdown = dir.join("table1.md");
        crate::frame::write_atomically(&json, self.json()?.as_bytes())?;
        crate::frame::write_atomically(&markdown, self.markdown().as_bytes())?;
        Ok([json, markdown])
    }
}
