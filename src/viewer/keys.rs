//! The viewer's keys as one table: the key handler looks presses up in it, and `view --help`
//! (and docs/viewer.md's key table, checked by a test) are printed from it, so the keys a person reads
//! about are the keys that act.

use winit::keyboard::{Key, NamedKey};

use super::controls::{AddedLight, Live};
use super::live::Settings;
use crate::frame::StencilMode;
use crate::scene::Scene;
use crate::technique::{LightMode, Normalize, OutlineMethod, ShadowMode, SilhouetteMethod, TECHNIQUES};

/// How far one press of an arrow turns or tilts the light (radians).
const LIGHT_STEP: f32 = 0.15;
/// The light's tilt stays within this many radians either way.
const MAX_TILT: f32 = 1.2;
/// The shadow-volume increments K cycles through.
const INCREMENTS: [u8; 4] = [1, 2, 4, 8];
/// The outline blur radii B cycles through (pixels; 0 is sharp).
const OUTLINE_BLURS: [u32; 3] = [0, 4, 8];
/// The sample counts M cycles through (those the device lacks are skipped, and named).
pub(super) const SAMPLE_COUNTS: [u32; 3] = [1, 2, 4];

/// A key as the table names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum KeyPress {
    /// Escape, Space, an arrow.
    Named(NamedKey),
    /// A letter, given lower-case, typed in either case (Shift and Caps Lock do not matter)...
    Letter(char),
    /// ...except where the letter typed upper-case (given upper-case) has its own binding.
    Upper(char),
}

impl KeyPress {
    /// The key as the help text names it.
    fn label(self) -> String {
        match self {
            KeyPress::Named(NamedKey::Escape) => "Esc".into(),
            KeyPress::Named(NamedKey::ArrowLeft) => "Left".into(),
            KeyPress::Named(NamedKey::ArrowRight) => "Right".into(),
            KeyPress::Named(NamedKey::ArrowUp) => "Up".into(),
            KeyPress::Named(NamedKey::ArrowDown) => "Down".into(),
            KeyPress::Named(other) => format!("{other:?}"),
            KeyPress::Letter(c) => c.to_uppercase().to_string(),
            KeyPress::Upper(c) => format!("Shift+{c}"),
        }
    }
}

/// What a key does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Action {
    NextTechnique,
    PreviousTechnique,
    SwitchStencil,
    NextNormalisation,
    NextIncrement,
    NextInk,
    NextOutlineMethod,
    NextOutlineBlur,
    SwitchAtlasLight,
    NextSampleCount,
    Pause,
    NextLight,
    PreviousLight,
    SwitchLightOff,
    AddPointLight,
    AddSpotLight,
    RemoveLight,
    SwitchShadowMode,
    TurnLight,
    TurnLightBack,
    TiltLight,
    TiltLightBack,
    Reset,
    Quit,
}

/// Whether the viewer goes on after an action.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Flow {
    Continue,
    Quit,
}

pub(super) struct Binding {
    pub keys: &'static [KeyPress],
    pub description: &'static str,
    pub action: Action,
}

/// Every key the viewer acts on, in the order the help lists them.
pub(super) const BINDINGS: &[Binding] = &[
    Binding {
        keys: &[KeyPress::Letter('t')],
        description: "next technique (all of them, in the order `view --help` lists)",
        action: Action::NextTechnique,
    },
    Binding { keys: &[KeyPress::Upper('T')], description: "previous technique", action: Action::PreviousTechnique },
    Binding {
        keys: &[KeyPress::Letter('s')],
        description: "stencil: emulated (alpha) / reference (real stencil)",
        action: Action::SwitchStencil,
    },
    Binding {
        keys: &[KeyPress::Letter('n')],
        description: "shadow-volume normalisation: seed, max, subpass",
        action: Action::NextNormalisation,
    },
    Binding {
        keys: &[KeyPress::Letter('k')],
        description: "shadow-volume increment k: 1, 2, 4, 8",
        action: Action::NextIncrement,
    },
    Binding {
        keys: &[KeyPress::Letter('e')],
        description: "silhouette/toon ink: edges, shader rim, inverted hull, alpha test, extrusion",
        action: Action::NextInk,
    },
    Binding {
        keys: &[KeyPress::Letter('o')],
        description: "outline copy: extruded along the normals / scaled about the centre (the document's)",
        action: Action::NextOutlineMethod,
    },
    Binding {
        keys: &[KeyPress::Letter('b')],
        description: "outline blur: 0 (sharp), 4, 8 pixels",
        action: Action::NextOutlineBlur,
    },
    Binding {
        keys: &[KeyPress::Letter('l')],
        description: "shadow-map/atlas light: fixed (baked once, cached) / moving (re-baked every frame)",
        action: Action::SwitchAtlasLight,
    },
    Binding {
        keys: &[KeyPress::Letter('m')],
        description: "MSAA: 1x, 2x, 4x samples per pixel (a count the device lacks is skipped, and named)",
        action: Action::NextSampleCount,
    },
    Binding {
        keys: &[KeyPress::Named(NamedKey::Space), KeyPress::Letter('p')],
        description:
            "pause / resume the animation (shadow casters turn about their vertical axis; animated models play)",
        action: Action::Pause,
    },
    Binding {
        keys: &[KeyPress::Letter('i')],
        description: "select the next light (the arrows move it; the title names it)",
        action: Action::NextLight,
    },
    Binding { keys: &[KeyPress::Upper('I')], description: "select the previous light", action: Action::PreviousLight },
    Binding {
        keys: &[KeyPress::Letter('x')],
        description: "switch the selected light off / on",
        action: Action::SwitchLightOff,
    },
    Binding {
        keys: &[KeyPress::Letter('a')],
        description: "add a point light above the target, and select it (its `--light` spec is printed)",
        action: Action::AddPointLight,
    },
    Binding {
        keys: &[KeyPress::Upper('A')],
        description: "add a spot light aimed at the target, and select it",
        action: Action::AddSpotLight,
    },
    Binding {
        keys: &[KeyPress::Upper('X')],
        description: "remove the selected light",
        action: Action::RemoveLight,
    },
    Binding {
        keys: &[KeyPress::Letter('v')],
        description: "shadow volumes and planar: additive (each light added where its shadow does not fall) / modulate (the seeds')",
        action: Action::SwitchShadowMode,
    },
    Binding {
        keys: &[KeyPress::Named(NamedKey::ArrowLeft)],
        description: "selected light: turn about the vertical axis",
        action: Action::TurnLight,
    },
    Binding {
        keys: &[KeyPress::Named(NamedKey::ArrowRight)],
        description: "selected light: turn about the vertical axis, the other way",
        action: Action::TurnLightBack,
    },
    Binding {
        keys: &[KeyPress::Named(NamedKey::ArrowUp)],
        description: "selected light: tilt (a point or spot light: raise)",
        action: Action::TiltLight,
    },
    Binding {
        keys: &[KeyPress::Named(NamedKey::ArrowDown)],
        description: "selected light: tilt the other way (lower)",
        action: Action::TiltLightBack,
    },
    Binding {
        keys: &[KeyPress::Letter('r')],
        description: "reset camera, lights and animation",
        action: Action::Reset,
    },
    Binding {
        keys: &[KeyPress::Named(NamedKey::Escape), KeyPress::Letter('q')],
        description: "quit",
        action: Action::Quit,
    },
];

/// The mouse's part, handled by the window's pointer events rather than looked up here; listed
/// with the keys.
const MOUSE: &[(&str, &str)] = &[("left drag", "orbit the camera"), ("wheel", "zoom")];

/// The action bound to `key`, if any.
pub(super) fn action_for(key: &Key) -> Option<Action> {
    let find = |pressed: &dyn Fn(KeyPress) -> bool| {
        BINDINGS.iter().find(|binding| binding.keys.iter().any(|k| pressed(*k))).map(|binding| binding.action)
    };
    match key {
        Key::Named(named) => find(&|k| k == KeyPress::Named(*named)),
        Key::Character(text) => find(&|k| matches!(k, KeyPress::Upper(c) if is_char(text, c))).or_else(|| {
            let lower = text.to_lowercase();
            find(&|k| matches!(k, KeyPress::Letter(c) if is_char(&lower, c)))
        }),
        _ => None,
    }
}

/// The action of the letter `letter` typed (as `action_for` of that character).
pub(super) fn action_for_letter(letter: char) -> Option<Action> {
    action_for(&Key::Character(letter.to_string().into()))
}

/// `--press-after`'s key: one character the key map binds.
pub(crate) fn scripted_key(text: &str) -> crate::error::Result<char> {
    let mut chars = text.chars();
    match (chars.next(), chars.next()) {
        (Some(c), None) if action_for_letter(c).is_some() => Ok(c),
        _ => Err(crate::error::Error::InvalidInput(format!(
            "--press-after: '{text}' is not a key the viewer binds; use one letter from `nostencil view --help`"
        ))),
    }
}

/// Whether `text` is exactly the one character `c`.
fn is_char(text: &str, c: char) -> bool {
    let mut chars = text.chars();
    chars.next() == Some(c) && chars.next().is_none()
}

impl Action {
    /// Changes what the next frame shows (`settings` rebuild the technique, `live` poses the
    /// scene); `base` is the scene as loaded, for a reset.
    pub(super) fn apply(self, settings: &mut Settings, live: &mut Live, base: &Scene) -> Flow {
        let s = &mut settings.render;
        match self {
            Action::NextTechnique => s.technique = cycle(TECHNIQUES, s.technique, 1),
            Action::PreviousTechnique => s.technique = cycle(TECHNIQUES, s.technique, -1),
            Action::SwitchStencil => {
                s.stencil = match s.stencil {
                    StencilMode::Emulated => StencilMode::Reference,
                    StencilMode::Reference => StencilMode::Emulated,
                }
            }
            Action::NextNormalisation => {
                s.shadow_volume.normalize = cycle(Normalize::ALL, s.shadow_volume.normalize, 1)
            }
            Action::NextIncrement => s.shadow_volume.increment = cycle(&INCREMENTS, s.shadow_volume.increment, 1),
            Action::NextInk => s.cartoon.silhouette = cycle(SilhouetteMethod::ALL, s.cartoon.silhouette, 1),
            Action::NextOutlineMethod => {
                s.cartoon.outline_method = cycle(OutlineMethod::ALL, s.cartoon.outline_method, 1)
            }
            Action::NextOutlineBlur => s.cartoon.outline_blur = cycle(&OUTLINE_BLURS, s.cartoon.outline_blur, 1),
            Action::SwitchAtlasLight => {
                s.shadow_atlas.light = cycle(&[LightMode::Fixed, LightMode::Moving], s.shadow_atlas.light, 1)
            }
            Action::NextSampleCount => s.samples = cycle(&SAMPLE_COUNTS, s.samples, 1),
            Action::Pause => live.paused = !live.paused,
            Action::NextLight => live.select_light(1),
            Action::PreviousLight => live.select_light(-1),
            Action::SwitchLightOff => {
                if let Some(light) = live.selected() {
                    light.off = !light.off;
                }
            }
            Action::AddPointLight | Action::AddSpotLight => {
                let kind = if self == Action::AddSpotLight { AddedLight::Spot } else { AddedLight::Point };
                match live.add_light(kind, base.camera.target) {
                    Ok(spec) => eprintln!("nostencil: added a light: --light '{spec}'"),
                    Err(why) => eprintln!("nostencil: no light added: {why}"),
                }
            }
            Action::RemoveLight => {
                if let Some(name) = live.remove_selected_light() {
                    eprintln!("nostencil: removed the light '{name}'");
                }
            }
            Action::SwitchShadowMode => s.shadow_mode = cycle(ShadowMode::ALL, s.shadow_mode, 1),
            Action::TurnLight | Action::TurnLightBack | Action::TiltLight | Action::TiltLightBack => {
                if let Some(turn) = live.selected().map(|l| &mut l.turn) {
                    match self {
                        Action::TurnLight => turn.yaw -= LIGHT_STEP,
                        Action::TurnLightBack => turn.yaw += LIGHT_STEP,
                        Action::TiltLight => turn.tilt = (turn.tilt + LIGHT_STEP).min(MAX_TILT),
                        _ => turn.tilt = (turn.tilt - LIGHT_STEP).max(-MAX_TILT),
                    }
                }
            }
            Action::Reset => live.reset(base),
            Action::Quit => return Flow::Quit,
        }
        Flow::Continue
    }
}

/// The item `step` places after `current` in `all`, wrapping (the first when `current` is not
/// in `all`).
fn cycle<T: Copy + PartialEq>(all: &[T], current: T, step: isize) -> T {
    let n = all.len() as isize;
    match all.iter().position(|x| *x == current) {
        Some(i) => all[(i as isize + step).rem_euclid(n) as usize],
        None => all[0],
    }
}

/// (keys, description) rows: the key bindings, then the mouse.
fn rows() -> Vec<(String, &'static str)> {
    let keys = BINDINGS.iter().map(|binding| {
        let labels: Vec<String> = binding.keys.iter().map(|k| k.label()).collect();
        (labels.join(" or "), binding.description)
    });
    keys.chain(MOUSE.iter().map(|(input, does)| (input.to_string(), *does))).collect()
}

/// The text `nostencil view --help` ends with.
pub(crate) fn help() -> String {
    let rows = rows();
    let width = rows.iter().map(|(keys, _)| keys.len()).max().unwrap_or(0);
    let mut text = String::from("Keys and mouse in the window:\n");
    for (keys, description) in &rows {
        text += &format!("  {keys:<width$}  {description}\n");
    }
    let techniques: Vec<&str> = TECHNIQUES.iter().map(|t| t.name()).collect();
    text += &format!("\nT goes through the techniques in this order: {}.", techniques.join(", "));
    text
}

/// The same rows as a Markdown table (docs/viewer.md's).
#[cfg(test)]
fn markdown_table() -> String {
    let mut table = String::from("| input | does |\n|---|---|\n");
    for (keys, description) in rows() {
        table += &format!("| {keys} | {description} |\n");
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;
    use winit::keyboard::SmolStr;

    #[test]
    fn every_key_is_bound_once_and_described() {
        let presses: Vec<KeyPress> = BINDINGS.iter().flat_map(|b| b.keys.iter().copied()).collect();
        for (i, press) in presses.iter().enumerate() {
            assert!(!presses[..i].contains(press), "{press:?} is bound twice");
        }
        let labels: Vec<String> = presses.iter().map(|p| p.label()).collect();
        for (i, label) in labels.iter().enumerate() {
            assert!(!labels[..i].contains(label), "two keys print as {label}");
        }
        for binding in BINDINGS {
            assert!(!binding.keys.is_empty(), "{:?} has no key", binding.action);
            assert!(!binding.description.trim().is_empty(), "{:?} has no description", binding.action);
        }
    }

    #[test]
    fn each_key_finds_its_own_action() {
        for binding in BINDINGS {
            for press in binding.keys {
                let keys = match *press {
                    KeyPress::Named(named) => vec![Key::Named(named)],
                    KeyPress::Letter(c) => {
                        let upper = c.to_ascii_uppercase();
                        let mut keys = vec![Key::Character(SmolStr::new(c.to_string()))];
                        // Caps Lock types the letter upper-case: it acts alike unless Shift+letter
                        // has a binding of its own.
                        if !BINDINGS.iter().any(|b| b.keys.contains(&KeyPress::Upper(upper))) {
                            keys.push(Key::Character(SmolStr::new(upper.to_string())));
                        }
                        keys
                    }
                    KeyPress::Upper(c) => vec![Key::Character(SmolStr::new(c.to_string()))],
                };
                for key in keys {
                    assert_eq!(action_for(&key), Some(binding.action), "{key:?}");
                }
            }
        }
        assert_eq!(action_for(&Key::Character(SmolStr::new("z"))), None);
        assert_eq!(action_for(&Key::Named(NamedKey::Tab)), None);
    }

    #[test]
    fn the_readme_key_table_is_the_map() {
        let readme = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/viewer.md"));
        let start = readme.find("| input | does |").expect("docs/viewer.md has a key table");
        let table: String =
            readme[start..].lines().take_while(|line| line.starts_with('|')).map(|line| format!("{line}\n")).collect();
        assert_eq!(table, markdown_table(), "docs/viewer.md's key table differs from keys.rs; paste the right side");
    }

    #[test]
    fn the_help_lists_every_key() {
        let help = help();
        for binding in BINDINGS {
            assert!(help.contains(binding.description), "{}", binding.description);
        }
        assert!(help.contains("Shift+T") && help.contains("left drag"), "{help}");
    }
}
