//! Fill-rate budgets for CI: the deterministic counters of a frame (samples passed, fragment
//! invocations, draws, per pass) recorded once and compared on every later run. Samples passed
//! are exact on any conformant device, so a CI machine on software Vulkan can guard fill rate.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::frame::bandwidth::Bandwidth;
use crate::render::FrameCounters;

pub const BUDGET_SCHEMA: &str = "nostencil-budget/1";

/// The deterministic counters of one pass (of this crate's frame, or one render pass instance of
/// an application measured by the fill-rate layer) under the name its budget has: what a budget
/// records, and what a run is checked with.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct PassBudget {
    pub name: String,
    pub draws: u32,
    pub samples_passed: u64,
    /// None where the device had no pipeline statistics when the budget was written.
    pub fragment_invocations: Option<u64>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Budget {
    pub schema: String,
    pub scene: String,
    pub technique: String,
    pub stencil: String,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel of the recorded frame (samples passed count every sample); budgets
    /// written before MSAA have none and were one-sample frames.
    #[serde(default = "one_sample")]
    pub samples: u32,
    pub passes: Vec<PassBudget>,
    /// Bytes per frame on a tiler and an immediate-mode GPU (frame/bandwidth.rs); budgets
    /// written before the estimate have none and hold no bytes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame_bandwidth: Option<Bandwidth>,
    /// An application's compute and transfer work outside render passes, by position (budgets
    /// written before the layer measured it have none, and check none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub work: Vec<WorkBudget>,
}

/// The deterministic figures of one dispatch group or transfer of an application's frame,
/// the most over the measured frames.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct WorkBudget {
    /// "compute #0", "transfer #3 'upload'": kind, position among the frame's work, label.
    pub name: String,
    pub workgroups: Option<u64>,
    pub compute_invocations: Option<u64>,
    /// Bytes read and written (transfers).
    pub bytes: u64,
}

fn one_sample() -> u32 {
    1
}

/// `technique` of a budget recorded from an application by `nostencil profile-app`: its passes
/// are the application's render pass instances, by position in the frame.
pub const APPLICATION_TECHNIQUE: &str = "application";

/// The name an application's render pass has in its budget: its position and label.
pub fn application_pass_name(position: u32, label: Option<&str>) -> String {
    match label {
        Some(label) => format!("render pass #{position} '{label}'"),
        None => format!("render pass #{position}"),
    }
}

/// One counter of one pass (or work row, or the frame's bytes) against its budget.
#[derive(Debug, Clone, PartialEq)]
pub struct BudgetFigure {
    pub pass: String,
    pub counter: &'static str,
    pub budget: u64,
    pub actual: u64,
}

impl BudgetFigure {
    pub fn over(&self) -> bool {
        self.actual > self.budget
    }

    /// How far from its budget, in percent of it (+: over; infinite over a budget of 0).
    pub fn margin_percent(&self) -> f64 {
        if self.budget > 0 {
            (self.actual as f64 / self.budget as f64 - 1.0) * 100.0
        } else if self.actual > 0 {
            f64::INFINITY
        } else {
            0.0
        }
    }

    /// "samples passed 80000 of 72000 (+11.1%)", for a margin column.
    pub fn brief(&self) -> String {
        format!("{} {} of {} ({:+.1}%)", self.counter, self.actual, self.budget, self.margin_percent())
    }
}

impl std::fmt::Display for BudgetFigure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let percent =
            if self.budget > 0 { (self.actual as f64 / self.budget as f64 - 1.0) * 100.0 } else { f64::INFINITY };
        write!(f, "pass '{}': {} {} > budget {} (+{percent:.1}%)", self.pass, self.counter, self.actual, self.budget)
    }
}

/// The counters of each pass of this crate's frame.
fn frame_passes(counters: &FrameCounters) -> Vec<PassBudget> {
    counters
        .passes
        .iter()
        .map(|p| PassBudget {
            name: p.name.clone(),
            draws: p.draws,
            samples_passed: p.samples_passed,
            fragment_invocations: p.fragment_invocations,
        })
        .collect()
}

impl Budget {
    pub fn from_frame(scene: &str, technique: &str, stencil: &str, counters: &FrameCounters) -> Self {
        Budget {
            schema: BUDGET_SCHEMA.into(),
            scene: scene.into(),
            technique: technique.into(),
            stencil: stencil.into(),
            width: counters.width,
            height: counters.height,
            samples: counters.samples,
            passes: frame_passes(counters),
            frame_bandwidth: Some(counters.bandwidth()),
            work: Vec::new(),
        }
    }

    /// A budget for an application's frame (`profile-app`): `scene` is the application's name,
    /// `width` x `height` the largest render area, and the passes its render pass instances.
    pub fn for_application(
        application: &str,
        width: u32,
        height: u32,
        passes: &[PassBudget],
        frame_bandwidth: Bandwidth,
        work: &[WorkBudget],
    ) -> Self {
        Budget {
            schema: BUDGET_SCHEMA.into(),
            scene: application.into(),
            technique: APPLICATION_TECHNIQUE.into(),
            stencil: "n/a".into(),
            width,
            height,
            samples: 1,
            passes: passes.to_vec(),
            frame_bandwidth: Some(frame_bandwidth),
            work: work.to_vec(),
        }
    }

    /// Every figure of an application's passes, work and bytes the budget holds, over it or
    /// not (`over()` picks those over it: the verdict; the HTML page and the JUnit XML show
    /// all, with their margins). The frame size is not compared: a larger window is what the
    /// budget is there to catch. A budget of another kind, another application's, or a pass it
    /// does not list is an error naming it.
    pub fn compared_application(
        &self,
        application: &str,
        passes: &[PassBudget],
        frame_bandwidth: Bandwidth,
        work: &[WorkBudget],
    ) -> Result<Vec<BudgetFigure>> {
        self.check_application_kind(application)?;
        let mut figures = self.pass_figures(passes)?;
        figures.extend(self.work_figures(work)?);
        figures.extend(self.bandwidth_figures(frame_bandwidth));
        Ok(figures)
    }

    /// An error unless the budget is for application `application`.
    fn check_application_kind(&self, application: &str) -> Result<()> {
        if self.technique != APPLICATION_TECHNIQUE {
            return Err(Error::InvalidInput(format!(
                "the budget is for nostencil's own frame ({} / {}), not an application: record one with \
                 `profile-app --record-budget`",
                self.scene, self.technique
            )));
        }
        if self.scene != application {
            return Err(Error::InvalidInput(format!(
                "the budget is for application '{}', not '{application}'",
                self.scene
            )));
        }
        Ok(())
    }

    /// Every figure of the application's work the budget holds; none for a budget that holds
    /// no work (written before the layer measured it), an error for work it does not list.
    fn work_figures(&self, work: &[WorkBudget]) -> Result<Vec<BudgetFigure>> {
        let mut overruns = Vec::new();
        if self.work.is_empty() {
            return Ok(overruns);
        }
        for w in work {
            let budget = self
                .work
                .iter()
                .find(|b| b.name == w.name)
                .ok_or_else(|| Error::InvalidInput(format!("'{}' has no budget (record a new one)", w.name)))?;
            let figures = [
                ("workgroups", budget.workgroups, w.workgroups),
                ("compute invocations", budget.compute_invocations, w.compute_invocations),
                ("bytes moved", Some(budget.bytes), Some(w.bytes)),
            ];
            for (counter, budget, actual) in figures {
                if let (Some(budget), Some(actual)) = (budget, actual) {
                    overruns.push(BudgetFigure { pass: w.name.clone(), counter, budget, actual });
                }
            }
        }
        Ok(overruns)
    }

    /// The frame's bytes against the budget's (none when the budget holds no bytes).
    fn bandwidth_figures(&self, actual: Bandwidth) -> Vec<BudgetFigure> {
        let Some(budget) = self.frame_bandwidth else { return Vec::new() };
        let figures = [
            ("tiler bytes per frame", budget.tiler_bytes, actual.tiler_bytes),
            ("immediate-mode bytes per frame", budget.immediate_bytes, actual.immediate_bytes),
        ];
        figures
            .into_iter()
            .map(|(counter, budget, actual)| BudgetFigure { pass: "frame".into(), counter, budget, actual })
            .collect()
    }

    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
        let budget: Budget = serde_json::from_str(&text)
            .map_err(|e| Error::Asset { path: path.to_path_buf(), problem: format!("not a budget file: {e}") })?;
        if budget.schema != BUDGET_SCHEMA {
            return Err(Error::Asset {
                path: path.to_path_buf(),
                problem: format!("budget schema '{}', expected '{BUDGET_SCHEMA}'", budget.schema),
            });
        }
        Ok(budget)
    }

    /// Written to a temporary file and renamed, like every output.
    pub fn write(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(|e| Error::Internal(e.to_string()))?;
        crate::frame::write_atomically(path, text.as_bytes())
    }

    /// Every figure of this crate's frame the budget holds, over it or not (`over()` picks
    /// those over it); an error when the frame is not the one the budget describes.
    pub fn compared(
        &self,
        scene: &str,
        technique: &str,
        stencil: &str,
        counters: &FrameCounters,
    ) -> Result<Vec<BudgetFigure>> {
        let what = (self.scene.as_str(), self.technique.as_str(), self.stencil.as_str(), self.width, self.height);
        if what != (scene, technique, stencil, counters.width, counters.height) {
            return Err(Error::InvalidInput(format!(
                "the budget is for scene {} / {} / stencil {} at {}x{}, not scene {scene} / {technique} / stencil {stencil} at {}x{}",
                self.scene, self.technique, self.stencil, self.width, self.height, counters.width, counters.height
            )));
        }
        if self.samples != counters.samples {
            return Err(Error::InvalidInput(format!(
                "the budget is for {}x MSAA, the frame has {}x: record a budget at --samples {} or check at --samples {}",
                self.samples, counters.samples, counters.samples, self.samples
            )));
        }
        let mut figures = self.pass_figures(&frame_passes(counters))?;
        figures.extend(self.bandwidth_figures(counters.bandwidth()));
        Ok(figures)
    }

    /// Every counter the budget holds, pass by pass (matched by name).
    fn pass_figures(&self, passes: &[PassBudget]) -> Result<Vec<BudgetFigure>> {
        let mut overruns = Vec::new();
        for pass in passes {
            let budget =
                self.passes.iter().find(|b| b.name == pass.name).ok_or_else(|| {
                    Error::InvalidInput(format!("pass '{}' has no budget (record a new one)", pass.name))
                })?;
            let mut over = |counter, budget: u64, actual: u64| {
                overruns.push(BudgetFigure { pass: pass.name.clone(), counter, budget, actual });
            };
            over("draws", budget.draws as u64, pass.draws as u64);
            over("samples passed", budget.samples_passed, pass.samples_passed);
            if let (Some(b), Some(a)) = (budget.fragment_invocations, pass.fragment_invocations) {
                over("fragment invocations", b, a);
            }
        }
        Ok(overruns)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The verdict: the figures over budget.
    fn check(
        budget: &Budget,
        scene: &str,
        technique: &str,
        stencil: &str,
        c: &FrameCounters,
    ) -> Result<Vec<BudgetFigure>> {
        Ok(budget.compared(scene, technique, stencil, c)?.into_iter().filter(BudgetFigure::over).collect())
    }

    fn check_application(
        budget: &Budget,
        application: &str,
        passes: &[PassBudget],
        bytes: Bandwidth,
        work: &[WorkBudget],
    ) -> Result<Vec<BudgetFigure>> {
        let figures = budget.compared_application(application, passes, bytes, work)?;
        Ok(figures.into_iter().filter(BudgetFigure::over).collect())
    }
    use crate::render::PassCounters;

    fn frame(samples: u64) -> FrameCounters {
        let pass = |name: &str, samples| PassCounters {
            name: name.into(),
            own_draw: None,
            light: None,
            draws: 2,
            commands: 0,
            vertex_invocations: Some(6),
            clipping_primitives: Some(2),
            fragment_invocations: Some(samples + 100),
            samples_passed: samples,
            gpu_ms: 1.0,
            start_ms: 0.0,
            render_pass_instances: Vec::new(),
        };
        FrameCounters {
            width: 8,
            height: 8,
            samples: 1,
            passes: vec![pass("scene", 64), pass("overlay", samples)],
            render_passes: Vec::new(),
            render_pass_instances: Vec::new(),
            cpu: Default::default(),
        }
    }

    #[test]
    fn recorded_frame_passes_and_a_costlier_one_fails_by_name() {
        let budget = Budget::from_frame("s", "t", "emulated", &frame(10));
        assert!(check(&budget, "s", "t", "emulated", &frame(10)).unwrap().is_empty());
        let overruns = check(&budget, "s", "t", "emulated", &frame(30)).unwrap();
        assert_eq!(overruns.len(), 2);
        assert!(overruns.iter().all(|o| o.pass == "overlay"));
        assert!(overruns[0].to_string().contains("pass 'overlay': samples passed 30 > budget 10"));
        assert!(check(&budget, "s", "t", "emulated", &FrameCounters { width: 16, ..frame(10) }).is_err());
    }

    #[test]
    fn an_application_budget_is_checked_by_pass_name_whatever_the_size() {
        let pass = |samples| PassBudget {
            name: "render pass #0".into(),
            draws: 1,
            samples_passed: samples,
            fragment_invocations: Some(samples),
        };
        let bytes = |tiler, immediate| Bandwidth { tiler_bytes: tiler, immediate_bytes: immediate };
        let budget = Budget::for_application("vkcube", 500, 500, &[pass(1000)], bytes(100, 200), &[]);
        assert!(check_application(&budget, "vkcube", &[pass(1000)], bytes(100, 200), &[]).unwrap().is_empty());
        let overruns = check_application(&budget, "vkcube", &[pass(1500)], bytes(100, 200), &[]).unwrap();
        assert_eq!(overruns.len(), 2);
        assert!(overruns[0].to_string().contains("pass 'render pass #0': samples passed 1500 > budget 1000"));
        // Bytes per frame are held too, named by the frame.
        let overruns = check_application(&budget, "vkcube", &[pass(1000)], bytes(101, 200), &[]).unwrap();
        assert_eq!(overruns.len(), 1);
        assert!(overruns[0].to_string().contains("pass 'frame': tiler bytes per frame 101 > budget 100"));
        assert!(check_application(&budget, "other", &[pass(1000)], bytes(0, 0), &[]).is_err());
        let extra = PassBudget { name: "render pass #1".into(), ..pass(1) };
        assert!(check_application(&budget, "vkcube", &[pass(1), extra], bytes(0, 0), &[]).is_err());
        let own = Budget::from_frame("s", "t", "emulated", &frame(10));
        assert!(check_application(&own, "s", &[pass(1)], bytes(0, 0), &[]).is_err());
    }

    #[test]
    fn an_applications_work_is_checked_by_name_and_old_budgets_check_none() {
        let work = |invocations| WorkBudget {
            name: "compute #0 'blur'".into(),
            workgroups: Some(16),
            compute_invocations: Some(invocations),
            bytes: 0,
        };
        let bytes = Bandwidth::default();
        let budget = Budget::for_application("app", 0, 0, &[], bytes, &[work(1024)]);
        assert!(check_application(&budget, "app", &[], bytes, &[work(1024)]).unwrap().is_empty());
        let overruns = check_application(&budget, "app", &[], bytes, &[work(2048)]).unwrap();
        assert_eq!(overruns.len(), 1);
        assert!(overruns[0].to_string().contains("'compute #0 'blur'': compute invocations 2048 > budget 1024"));
        let other = WorkBudget { name: "transfer #1".into(), ..work(0) };
        assert!(check_application(&budget, "app", &[], bytes, std::slice::from_ref(&other)).is_err());
        let old = Budget::for_application("app", 0, 0, &[], bytes, &[]);
        assert!(check_application(&old, "app", &[], bytes, &[other]).unwrap().is_empty());
    }
}
