//! `profile --compare a,b,...`: several variants of one frame in one table, pass rows side by
//! side, with frame totals and ratios to the first variant.

use std::fmt::Write as _;

use serde::Serialize;

use crate::render::FrameCounters;

#[derive(Debug, Clone, Serialize)]
pub struct VariantFrame {
    pub variant: String,
    pub counters: FrameCounters,
}

#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    pub schema: &'static str,
    pub variants: Vec<VariantFrame>,
    /// Per variant: (fragments, samples, GPU ms) of the frame divided by the first variant's.
    pub ratios: Vec<VariantRatio>,
}

#[derive(Debug, Clone, Serialize)]
pub struct VariantRatio {
    pub variant: String,
    pub fragment_invocations: Option<f64>,
    pub samples_passed: f64,
    pub gpu_ms: f64,
}

impl Comparison {
    pub fn new(variants: Vec<VariantFrame>) -> Self {
        let ratios = match variants.first() {
            None => Vec::new(),
            Some(first) => {
                let base = &first.counters;
                variants
                    .iter()
                    .map(|v| VariantRatio {
                        variant: v.variant.clone(),
                        fragment_invocations: v
                            .counters
                            .total_fragment_invocations()
                            .zip(base.total_fragment_invocations())
                            .map(|(a, b)| a as f64 / b.max(1) as f64),
                        samples_passed: v.counters.total_samples_passed() as f64
                            / base.total_samples_passed().max(1) as f64,
                        gpu_ms: v.counters.total_gpu_ms() / base.total_gpu_ms().max(1e-9),
                    })
                    .collect()
            }
        };
        Comparison { schema: "nostencil-compare/1", variants, ratios }
    }

    /// Pass names in order of first appearance over all variants.
    fn pass_names(&self) -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for v in &self.variants {
            for p in &v.counters.passes {
                if !names.contains(&p.name) {
                    names.push(p.name.clone());
                }
            }
        }
        names
    }

    pub fn table(&self) -> String {
        let mut out = String::new();
        let names = self.pass_names();
        let width = names.iter().map(|n| n.len()).max().unwrap_or(4).max(16);
        let _ = write!(out, "{:<width$}", "pass");
        for v in &self.variants {
            let _ = write!(out, " | {:^34}", v.variant);
        }
        let _ = writeln!(out);
        let _ = write!(out, "{:<width$}", "");
        for _ in &self.variants {
            let _ = write!(out, " | {:>12} {:>12} {:>8}", "fragments", "samples", "GPU ms");
        }
        let _ = writeln!(out);
        let cell = |out: &mut String, f: Option<u64>, s: Option<u64>, ms: Option<f64>| {
            let text = |v: Option<u64>| v.map_or("-".to_owned(), |v| v.to_string());
            let _ = write!(
                out,
                " | {:>12} {:>12} {:>8}",
                text(f),
                text(s),
                ms.map_or("-".to_owned(), |m| format!("{m:.2}"))
            );
        };
        for name in &names {
            let _ = write!(out, "{name:<width$}");
            for v in &self.variants {
                let pass = v.counters.pass(name);
                cell(
                    &mut out,
                    pass.and_then(|p| p.fragment_invocations),
                    pass.map(|p| p.samples_passed),
                    pass.map(|p| p.gpu_ms),
                );
            }
            let _ = writeln!(out);
        }
        let _ = write!(out, "{:<width$}", "frame");
        for v in &self.variants {
            let c = &v.counters;
            cell(&mut out, c.total_fragment_invocations(), Some(c.total_samples_passed()), Some(c.total_gpu_ms()));
        }
        let _ = writeln!(out);
        let _ = write!(out, "{:<width$}", format!("ratio to {}", self.variants.first().map_or("", |v| &v.variant)));
        for r in &self.ratios {
            let _ = write!(
                out,
                " | {:>12} {:>12} {:>8}",
                r.fragment_invocations.map_or("-".to_owned(), |x| format!("{x:.2}x")),
                format!("{:.2}x", r.samples_passed),
                format!("{:.2}x", r.gpu_ms)
            );
        }
        let _ = writeln!(out);
        out
    }

    pub fn csv(&self) -> String {
        let mut out = String::from("variant,pass,draws,fragment_invocations,samples_passed,gpu_ms\n");
        for v in &self.variants {
            for p in &v.counters.passes {
                let _ = writeln!(
                    out,
                    "{},{},{},{},{},{:.6}",
                    v.variant,
                    p.name,
                    p.draws,
                    p.fragment_invocations.map_or(String::new(), |f| f.to_string()),
                    p.samples_passed,
                    p.gpu_ms
                );
            }
        }
        out
    }
}
