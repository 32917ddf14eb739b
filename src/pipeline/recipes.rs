//! Named fixed-function recipes (docs/design/: shadow-volumes, planar-shadows, outlines,
//! shadow-atlas), each defined once: the write masks,
//! the alpha-counter steps, the modulations and the stencil faces of the reference paths.
//! Techniques build their pass plans from these names, so `nostencil passes` prints a recipe
//! by the name a port would look it up under.

use ash::vk;

use super::state::{BlendEquation, BlendState, StencilFace, StencilState};

/// Colour channels only: the counter in alpha is left alone.
pub const RGB_ONLY: vk::ColorComponentFlags =
    vk::ColorComponentFlags::from_raw(vk::ColorComponentFlags::RGBA.as_raw() & !vk::ColorComponentFlags::A.as_raw());

/// The counter alone: colour is left alone.
pub const ALPHA_ONLY: vk::ColorComponentFlags = vk::ColorComponentFlags::A;

const ONE: vk::BlendFactor = vk::BlendFactor::ONE;

/// Blending on the alpha channel only (colour masked off).
pub const fn alpha_blend(op: vk::BlendOp, src: vk::BlendFactor, dst: vk::BlendFactor) -> BlendState {
    BlendState { colour: None, alpha: Some(BlendEquation::new(op, src, dst)), write_mask: ALPHA_ONLY }
}

/// Blending on the colour channels only (the counter masked off).
pub const fn colour_blend(op: vk::BlendOp, src: vk::BlendFactor, dst: vk::BlendFactor) -> BlendState {
    BlendState { colour: Some(BlendEquation::new(op, src, dst)), alpha: None, write_mask: RGB_ONLY }
}

/// Colour written as the fragment gives it, alpha left alone.
pub const COLOUR_REPLACE: BlendState = BlendState { colour: None, alpha: None, write_mask: RGB_ONLY };

/// Nothing written: a pass that only tests (or only changes the stencil).
pub const NO_WRITE: BlendState = BlendState { colour: None, alpha: None, write_mask: vk::ColorComponentFlags::empty() };

// ---------------------------------------------------------------------------------------------
// The alpha counter (docs/design/shadow-volumes.md).

/// A volume wall entering: alpha += k/255.
pub const COUNTER_INCREMENT: BlendState = alpha_blend(vk::BlendOp::ADD, ONE, ONE);

/// A volume wall leaving: alpha -= k/255, clamped at 0.
pub const COUNTER_DECREMENT: BlendState = alpha_blend(vk::BlendOp::REVERSE_SUBTRACT, ONE, ONE);

/// N0: 1 - 2a, so that lit pixels (a = 0) become 1.
pub const NORMALISE_N0: BlendState = alpha_blend(vk::BlendOp::SUBTRACT, vk::BlendFactor::ONE_MINUS_DST_ALPHA, ONE);

/// One iteration: a*a - (1 - a); 1 stays 1, a deficit d grows to 3d - d*d.
pub const NORMALISE_ITERATION: BlendState =
    alpha_blend(vk::BlendOp::REVERSE_SUBTRACT, vk::BlendFactor::ONE_MINUS_DST_ALPHA, vk::BlendFactor::DST_ALPHA);

/// The seed's darkness, first half: alpha = max(alpha - D, 0).
pub const DARKNESS_SUBTRACT: BlendState = alpha_blend(vk::BlendOp::REVERSE_SUBTRACT, ONE, ONE);

/// The seed's darkness, second half: alpha += D (0 becomes D, 1 - D becomes 1).
pub const DARKNESS_ADD: BlendState = alpha_blend(vk::BlendOp::ADD, ONE, ONE);

/// Both halves at once: alpha = max(alpha, D).
pub const DARKNESS_MAX: BlendState = alpha_blend(vk::BlendOp::MAX, ONE, ONE);

// ---------------------------------------------------------------------------------------------
// Modulations: the shadow applied to the lit colour.

/// colour *= destination alpha (the normalised counter: 1 lit, D shadowed).
pub const MODULATE_BY_DST_ALPHA: BlendState =
    colour_blend(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::DST_ALPHA);

/// colour *= source alpha (the factor the shader outputs).
pub const MODULATE_BY_SRC_ALPHA: BlendState =
    colour_blend(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::SRC_ALPHA);

/// colour = source * (1 - dst alpha) + dst * dst alpha: draws only where alpha is 0 (the
/// stencil-free "not selected" test of the outline), colour only.
pub const COLOUR_WHERE_ALPHA_ZERO: BlendState =
    colour_blend(vk::BlendOp::ADD, vk::BlendFactor::ONE_MINUS_DST_ALPHA, vk::BlendFactor::DST_ALPHA);

// ---------------------------------------------------------------------------------------------
// The additive loop (docs/shadow-volumes.md, "Several lights"): per light, a down-counter in
// alpha (1 = a count of 0), its mask, and the light added where the mask holds 1.

/// A volume wall entering, counting down from 1: alpha -= k/255, clamped at 0.
pub const COUNTER_DOWN_ENTER: BlendState = alpha_blend(vk::BlendOp::REVERSE_SUBTRACT, ONE, ONE);

/// A volume wall leaving: alpha += k/255, clamped at 1 (a negative count stays lit).
pub const COUNTER_DOWN_LEAVE: BlendState = alpha_blend(vk::BlendOp::ADD, ONE, ONE);

/// The subpass mask: alpha := 0 where the shader finds the light's count above 0 (written
/// without a blend; colour masked off).
pub const MASK_SHADOWED: BlendState = BlendState { colour: None, alpha: None, write_mask: ALPHA_ONLY };

/// One light's shading: colour += the light's contribution x destination alpha (the mask: 1
/// lit, 0 shadowed), and alpha := the fragment's 1, which resets the counter for the next light
/// in the same pass: blend factors read the destination before the fragment is written.
pub const ADD_LIGHT_WHERE_LIT_RESET: BlendState = BlendState {
    colour: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::DST_ALPHA, ONE)),
    alpha: Some(BlendEquation::new(vk::BlendOp::ADD, ONE, vk::BlendFactor::ZERO)),
    write_mask: vk::ColorComponentFlags::RGBA,
};

/// The reference's shading: colour += the light's contribution where the stencil test passes.
pub const ADD_LIGHT: BlendState = colour_blend(vk::BlendOp::ADD, ONE, ONE);

/// One light's shading where the fragment itself says how much to add (0 where it read a
/// shadow): colour += the fragment's, alpha := the fragment's 1, which resets the counter.
pub const ADD_LIGHT_RESET: BlendState = BlendState {
    colour: Some(BlendEquation::new(vk::BlendOp::ADD, ONE, ONE)),
    alpha: Some(BlendEquation::new(vk::BlendOp::ADD, ONE, vk::BlendFactor::ZERO)),
    write_mask: vk::ColorComponentFlags::RGBA,
};

// ---------------------------------------------------------------------------------------------
// Ground shadows (docs/design/planar-shadows.md).

/// colour *= the fragment's colour (a factor per channel: a blob, a shadow-texture lookup, a
/// shadow volume's tint), alpha left alone.
pub const MODULATE_BY_SRC_COLOUR: BlendState =
    colour_blend(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::SRC_COLOR);

/// The planar shadow without a stencil: colour *= destination alpha (`1 - s` on a receiver not
/// yet shadowed, 1 elsewhere) and alpha := the fragment's 1, so that every later fragment on
/// the pixel multiplies by 1.
pub const MODULATE_BY_DST_ALPHA_ONCE: BlendState = BlendState {
    colour: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::DST_ALPHA)),
    alpha: Some(BlendEquation::new(vk::BlendOp::ADD, ONE, vk::BlendFactor::ZERO)),
    write_mask: vk::ColorComponentFlags::RGBA,
};

/// The planar shadow's stencil reference: colour *= the fragment's alpha (`1 - s`), which alpha
/// takes as well; the stencil lets one fragment per pixel through.
pub const MODULATE_BY_SRC_ALPHA_WRITING_ALPHA: BlendState = BlendState {
    colour: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ZERO, vk::BlendFactor::SRC_ALPHA)),
    alpha: None,
    write_mask: vk::ColorComponentFlags::RGBA,
};

// ---------------------------------------------------------------------------------------------
// Stencil faces of the real-stencil reference paths.

/// A face that compares `compare` against `reference` (all 8 bits) and applies `pass` where the
/// test and depth pass, `depth_fail` where depth fails; the stencil-test failure keeps.
pub const fn stencil_face(
    compare: vk::CompareOp,
    reference: u32,
    write_mask: u32,
    pass: vk::StencilOp,
    depth_fail: vk::StencilOp,
) -> StencilFace {
    StencilFace { compare, reference, compare_mask: 0xff, write_mask, fail: vk::StencilOp::KEEP, pass, depth_fail }
}

/// The same face on both sides.
pub const fn both_faces(face: StencilFace) -> StencilState {
    StencilState { front: face, back: face }
}

/// Writes `reference` where the fragment passes (the selection and receiver marks).
pub const fn stencil_replace(reference: u32) -> StencilState {
    both_faces(stencil_face(vk::CompareOp::ALWAYS, reference, 0xff, vk::StencilOp::REPLACE, vk::StencilOp::KEEP))
}

/// Passes where the stencil is `reference`, and writes nothing.
pub const fn stencil_equal(reference: u32) -> StencilState {
    both_faces(stencil_face(vk::CompareOp::EQUAL, reference, 0, vk::StencilOp::KEEP, vk::StencilOp::KEEP))
}

/// Passes where the stencil is not `reference`, and writes nothing.
pub const fn stencil_not_equal(reference: u32) -> StencilState {
    both_faces(stencil_face(vk::CompareOp::NOT_EQUAL, reference, 0, vk::StencilOp::KEEP, vk::StencilOp::KEEP))
}

/// Shadow-volume counting with a wrapping stencil: z-pass counts front faces up and back faces
/// down where the depth test passes; z-fail counts back faces up and front faces down where it
/// fails.
pub const fn stencil_volume_count(zfail: bool) -> StencilState {
    const INC: vk::StencilOp = vk::StencilOp::INCREMENT_AND_WRAP;
    const DEC: vk::StencilOp = vk::StencilOp::DECREMENT_AND_WRAP;
    const KEEP: vk::StencilOp = vk::StencilOp::KEEP;
    const ALWAYS: vk::CompareOp = vk::CompareOp::ALWAYS;
    if zfail {
        StencilState { front: stencil_face(ALWAYS, 0, 0xff, KEEP, DEC), back: stencil_face(ALWAYS, 0, 0xff, KEEP, INC) }
    } else {
        StencilState { front: stencil_face(ALWAYS, 0, 0xff, INC, KEEP), back: stencil_face(ALWAYS, 0, 0xff, DEC, KEEP) }
    }
}

/// The stencil value of a volume count of 0: the shadow-volume reference clears its stencil to
/// this, so that counts -128..=127 wrap to 0..=255 in order and a negative count (which the
/// clamping alpha counter holds as 0) stays below it.
pub const STENCIL_COUNT_ZERO: u32 = 0x80;

/// Passes where the biased volume count is positive (`0x80 < stencil`), and writes nothing:
/// the shadow-volume reference's one apply test, which leaves negative counts lit.
pub const STENCIL_COUNT_POSITIVE: StencilState =
    both_faces(stencil_face(vk::CompareOp::LESS, STENCIL_COUNT_ZERO, 0, vk::StencilOp::KEEP, vk::StencilOp::KEEP));

/// Passes where the biased count is not positive (`0x80 >= stencil`: lit, a negative count
/// included), and writes nothing: the additive reference's shading test, Ogre's `EQUAL 0` on
/// the repo's biased stencil.
pub const STENCIL_COUNT_NOT_POSITIVE: StencilState = both_faces(stencil_face(
    vk::CompareOp::GREATER_OR_EQUAL,
    STENCIL_COUNT_ZERO,
    0,
    vk::StencilOp::KEEP,
    vk::StencilOp::KEEP,
));

/// The seed 001 test: `Ref 0 Comp Equal Pass IncrWrap ZFail Keep` (a receiver pixel is darkened
/// once, then holds 1 and refuses the next shadow fragment).
pub const STENCIL_EQUAL_ZERO_THEN_INCREMENT: StencilState =
    both_faces(stencil_face(vk::CompareOp::EQUAL, 0, 0xff, vk::StencilOp::INCREMENT_AND_WRAP, vk::StencilOp::KEEP));

// ---------------------------------------------------------------------------------------------
// Blended (glTF BLEND) materials.

/// `rgb = src * a_src + dst * (1 - a_src)`, destination alpha kept (ZERO, ONE): alpha is the
/// technique's counter or mask, which a transparent surface must neither raise nor clear.
pub const OVER_KEEPING_ALPHA: BlendState = BlendState {
    colour: Some(BlendEquation::new(
        vk::BlendOp::ADD,
        vk::BlendFactor::SRC_ALPHA,
        vk::BlendFactor::ONE_MINUS_SRC_ALPHA,
    )),
    alpha: Some(BlendEquation::new(vk::BlendOp::ADD, vk::BlendFactor::ZERO, ONE)),
    write_mask: vk::ColorComponentFlags::RGBA,
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks_split_colour_from_the_counter() {
        assert_eq!(RGB_ONLY | ALPHA_ONLY, vk::ColorComponentFlags::RGBA);
        assert!((RGB_ONLY & ALPHA_ONLY).is_empty());
    }

    #[test]
    fn volume_counting_is_mirrored_between_methods() {
        let zpass = stencil_volume_count(false);
        let zfail = stencil_volume_count(true);
        assert_eq!(zpass.front.pass, vk::StencilOp::INCREMENT_AND_WRAP);
        assert_eq!(zpass.back.pass, vk::StencilOp::DECREMENT_AND_WRAP);
        assert_eq!(zfail.back.depth_fail, vk::StencilOp::INCREMENT_AND_WRAP);
        assert_eq!(zfail.front.depth_fail, vk::StencilOp::DECREMENT_AND_WRAP);
    }
}
