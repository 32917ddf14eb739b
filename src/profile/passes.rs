//! The `passes` table: every pass of a technique's plan with its fixed-function state, printed
//! from the very plan the renderer builds its pipelines from and records, as Markdown a port can
//! copy.

use std::fmt::Write as _;

use ash::vk;

use crate::pipeline::{BlendEquation, PipelineDesc, StencilFace};
use crate::render::plan::{PassKinds, PassPlan};

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

/// A Markdown table of one plan: one row per pipeline a pass binds, in the order they run,
/// with what the pass draws and pushes and when it runs.
pub fn plan_table<K: PassKinds>(title: &str, plan: &PassPlan<K>) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "### {title}\n");
    let _ = writeln!(
        out,
        "| # | pass | pipeline | target | runs | draws | push | shaders | colour blend | alpha blend | write mask | depth test | depth write | cull | depth bias | stencil front | stencil back |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for (index, pass) in plan.passes.iter().enumerate() {
        let target = pass.target.describe();
        let draws = match pass.scissored {
            true => format!("{}, inside the technique's scissors", pass.draws.describe()),
            false => pass.draws.describe().to_owned(),
        };
        let row = |pipeline: &str, state: String| {
            format!(
                "| {} | {} | {pipeline} | {target} | {} | {draws} | {} | {state} |",
                index + 1,
                pass.name,
                pass.when.describe(),
                pass.describe_push(),
            )
        };
        if pass.pipelines.is_empty() {
            // Transfer commands (mip blits): no pipeline, no fixed-function state.
            let _ = writeln!(out, "{}", row("(commands)", ["-"; 10].join(" | ")));
        }
        for desc in &pass.pipelines {
            let _ = writeln!(out, "{}", row(desc.name, state_columns(desc)));
        }
    }
    out
}

/// Shaders and fixed-function state of one pipeline, as table cells.
fn state_columns(desc: &PipelineDesc) -> String {
    let f = &desc.fixed;
    let (colour, alpha) = if f.blend.enabled() {
        (
            equation(Some(f.blend.colour.unwrap_or(BlendEquation::REPLACE))),
            equation(Some(f.blend.alpha.unwrap_or(BlendEquation::REPLACE))),
        )
    } else {
        (equation(None), equation(None))
    };
    format!(
        "{} + {} | {colour} | {alpha} | {} | {} | {} | {} | {} | {} | {}",
        desc.vertex_shader,
        desc.fragment_shader,
        write_mask(f.blend.write_mask),
        f.depth.compare.map_or("off".into(), short),
        if f.depth.write { "on" } else { "off" },
        if f.raster.cull.is_empty() { "NONE".into() } else { short(f.raster.cull) },
        f.raster.depth_bias.map_or("none".into(), |b| format!("{} const, {} slope", b.constant, b.slope)),
        f.stencil.map_or("none".into(), |s| stencil_face(&s.front)),
        f.stencil.map_or("none".into(), |s| stencil_face(&s.back)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::StencilMode;
    use crate::technique::light_loop::PlannedLight;
    use crate::technique::shadow_volume::{recipes, ShadowVolumeOptions, VolumeMethod};
    use crate::technique::ShadowMode;

    #[test]
    fn shadow_volume_table_shows_the_seed_recipes() {
        let options = ShadowVolumeOptions { method: VolumeMethod::ZPass, ..Default::default() };
        let lights = PlannedLight::default_lights();
        let plan =
            |stencil| recipes::plan(&options, ShadowMode::Modulate, Default::default(), stencil, 1, &lights).unwrap();
        let emulated = plan_table("emulated", &plan(StencilMode::Emulated));
        assert!(emulated.contains("| normalise N0 | normalise N0 |"));
        assert!(emulated.contains("| normalise N1 | normalise iteration |"));
        assert!(emulated.contains("SUBTRACT (ONE_MINUS_DST_ALPHA, ONE)"));
        assert!(emulated.contains("REVERSE_SUBTRACT (ONE_MINUS_DST_ALPHA, DST_ALPHA)"));
        // Emulated passes never use the stencil.
        for line in emulated.lines().filter(|l| l.starts_with("| ") && !l.starts_with("| #")) {
            assert!(line.ends_with("| none | none |"), "{line}");
        }
        let reference = plan_table("reference", &plan(StencilMode::Reference));
        assert!(reference.contains("INCREMENT_AND_WRAP"));
    }

    #[test]
    fn the_additive_table_shows_the_loop_of_each_light() {
        let options = ShadowVolumeOptions { method: VolumeMethod::ZPass, ..Default::default() };
        let lights = vec![
            PlannedLight { name: "sun".into(), shadows: true },
            PlannedLight { name: "lamp".into(), shadows: true },
            PlannedLight { name: "fill".into(), shadows: false },
        ];
        let plan =
            |stencil| recipes::plan(&options, ShadowMode::Additive, Default::default(), stencil, 1, &lights).unwrap();
        let emulated = plan_table("emulated", &plan(StencilMode::Emulated));
        for row in [
            "| scene (ambient) | scene (ambient) |",
            "| sun: volumes (alpha, z-pass) | volume enter (z-pass) |",
            "| sun: normalise N6 | normalise iteration |",
            "| lamp: normalise N1 | normalise iteration |",
            "| lamp: shading | shading |",
            "| fill: shading | shading (no shadows) |",
        ] {
            assert!(emulated.contains(row), "{row}\n{emulated}");
        }
        assert!(!emulated.contains("sun: normalise N7") && !emulated.contains("fill: volumes"));
        assert!(emulated.contains("ADD (DST_ALPHA, ONE) | ADD (ONE, ZERO)"), "the shading pass resets the counter");
        let reference = plan_table("reference", &plan(StencilMode::Reference));
        assert!(reference.contains("| lamp: shading (stencil) | shading (stencil) |"));
        assert!(reference.contains("GREATER_OR_EQUAL ref 128"));
    }
}
