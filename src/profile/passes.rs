//! The `passes` table: every pass of a technique with its fixed-function state, printed from the
//! very `PipelineDesc`s the renderer builds pipelines from, as Markdown a port can copy.

use std::fmt::Write as _;

use ash::vk;

use crate::pipeline::{BlendEquation, PipelineDesc, StencilFace};

fn short<T: std::fmt::Debug>(value: T) -> String {
    format!("{value:?}")
}

fn equation(eq: Option<BlendEquation>) -> String {
    match eq {
        None => "off (replace)".into(),
        Some(e) => format!("{} ({}, {})", short(e.op), short(e.src), short(e.dst)),
    }
}

fn write_mask(mask: vk::ColorComponentFlags) -> String {
    let channels: String = [
        (vk::ColorComponentFlags::R, 'R'),
        (vk::ColorComponentFlags::G, 'G'),
        (vk::ColorComponentFlags::B, 'B'),
        (vk::ColorComponentFlags::A, 'A'),
    ]
    .iter()
    .filter(|(flag, _)| mask.contains(*flag))
    .map(|(_, c)| *c)
    .collect();
    if channels.is_empty() {
        "none".into()
    } else {
        channels
    }
}

fn stencil_face(face: &StencilFace) -> String {
    format!(
        "{} ref {} mask {:#x}/{:#x}; pass {}, fail {}, depth-fail {}",
        short(face.compare),
        face.reference,
        face.compare_mask,
        face.write_mask,
        short(face.pass),
        short(face.fail),
        short(face.depth_fail)
    )
}

/// A Markdown table, one row per pass: `(path, desc)` as a technique's `pipeline_descs` lists them.
pub fn markdown_table(technique: &str, passes: &[(&str, PipelineDesc)]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "## {technique}: passes and fixed-function state\n");
    let _ = writeln!(
        out,
        "| path | pass | shaders | colour blend | alpha blend | write mask | depth test | depth write | cull | depth bias | stencil front | stencil back |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (path, desc) in passes {
        let f = &desc.fixed;
        let (colour, alpha) = if f.blend.enabled() {
            (
                equation(Some(f.blend.colour.unwrap_or(BlendEquation::REPLACE))),
                equation(Some(f.blend.alpha.unwrap_or(BlendEquation::REPLACE))),
            )
        } else {
            (equation(None), equation(None))
        };
        let _ = writeln!(
            out,
            "| {path} | {} | {} + {} | {colour} | {alpha} | {} | {} | {} | {} | {} | {} | {} |",
            desc.name,
            desc.vertex_shader,
            desc.fragment_shader,
            write_mask(f.blend.write_mask),
            f.depth.compare.map_or("off".into(), short),
            if f.depth.write { "on" } else { "off" },
            if f.raster.cull.is_empty() { "NONE".into() } else { short(f.raster.cull) },
            f.raster.depth_bias.map_or("none".into(), |b| format!("{} const, {} slope", b.constant, b.slope)),
            f.stencil.map_or("none".into(), |s| stencil_face(&s.front)),
            f.stencil.map_or("none".into(), |s| stencil_face(&s.back)),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::technique::shadow_volume::{pipeline_descs, ShadowVolumeOptions};

    #[test]
    fn shadow_volume_table_shows_the_seed_recipes() {
        let table = markdown_table("shadow-volume", &pipeline_descs(&ShadowVolumeOptions::default()));
        assert!(table.contains("| normalise N0 |"));
        assert!(table.contains("SUBTRACT (ONE_MINUS_DST_ALPHA, ONE)"));
        assert!(table.contains("REVERSE_SUBTRACT (ONE_MINUS_DST_ALPHA, DST_ALPHA)"));
        assert!(table.contains("INCREMENT_AND_WRAP"));
        // Emulated passes never use the stencil.
        for line in table.lines().filter(|l| l.starts_with("| emulated")) {
            assert!(line.ends_with("| none | none |"), "{line}");
        }
    }
}
