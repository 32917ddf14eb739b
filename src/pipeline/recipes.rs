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
#[cfg(test)]
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

    /// What a blend state leaves in the alpha channel, `src` the fragment's alpha and `dst`
    /// the pixel's (UNORM: the result clamped to 0..=1), for the factors and ops these recipes
    /// use.
    fn blended_alpha(state: BlendState, src: f32, dst: f32) -> f32 {
        if !state.write_mask.contains(vk::ColorComponentFlags::A) {
            return dst;
        }
        let Some(equation) = state.alpha else { return src };
        let factor = |f: vk::BlendFactor| match f {
            vk::BlendFactor::ZERO => 0.0,
            vk::BlendFactor::ONE => 1.0,
            vk::BlendFactor::DST_ALPHA => dst,
            vk::BlendFactor::ONE_MINUS_DST_ALPHA => 1.0 - dst,
            other => panic!("{other:?} is not modelled"),
        };
        let (s, d) = (src * factor(equation.src), dst * factor(equation.dst));
        let value = match equation.op {
            vk::BlendOp::ADD => s + d,
            vk::BlendOp::SUBTRACT => s - d,
            vk::BlendOp::REVERSE_SUBTRACT => d - s,
            // MIN and MAX take no factors.
            vk::BlendOp::MAX => src.max(dst),
            other => panic!("{other:?} is not modelled"),
        };
        value.clamp(0.0, 1.0)
    }

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() < 1e-6
    }

    #[test]
    fn the_counter_steps_and_the_normalisation_compute_their_documented_values() {
        let k = 4.0 / 255.0;
        // Two walls in, one out; a wall out of an empty pixel clamps at 0.
        let up = |a| blended_alpha(COUNTER_INCREMENT, k, a);
        let down = |a| blended_alpha(COUNTER_DECREMENT, k, a);
        assert!(close(down(up(up(0.0))), k));
        assert_eq!(down(0.0), 0.0);
        // Counting down from 1 (the additive loop): a wall in takes k off, one out gives it
        // back, clamped at 1.
        assert!(close(blended_alpha(COUNTER_DOWN_ENTER, k, 1.0), 1.0 - k));
        assert_eq!(blended_alpha(COUNTER_DOWN_LEAVE, k, 1.0), 1.0);
        // N0: 1 - 2a (the shader writes 1).
        assert!(close(blended_alpha(NORMALISE_N0, 1.0, 0.2), 0.6));
        assert_eq!(blended_alpha(NORMALISE_N0, 1.0, 0.0), 1.0);
        // An iteration: a deficit d = 0.1 grows to 3d - d*d = 0.29; 1 stays 1.
        assert!(close(blended_alpha(NORMALISE_ITERATION, 1.0, 0.9), 0.71));
        assert_eq!(blended_alpha(NORMALISE_ITERATION, 1.0, 1.0), 1.0);
        // The darkness D = 0.4, in two halves or at once: a shadow's 0 becomes D, 1 stays 1.
        for (a, darkened) in [(0.0, 0.4), (1.0, 1.0)] {
            let halves = blended_alpha(DARKNESS_ADD, 0.4, blended_alpha(DARKNESS_SUBTRACT, 0.4, a));
            assert!(close(halves, darkened), "{a}: {halves}");
            assert!(close(blended_alpha(DARKNESS_MAX, 0.4, a), darkened));
        }
    }

    #[test]
    fn the_counter_recipes_write_alpha_alone_and_the_colour_ones_leave_it() {
        let counter = [
            COUNTER_INCREMENT,
            COUNTER_DECREMENT,
            NORMALISE_N0,
            NORMALISE_ITERATION,
            DARKNESS_SUBTRACT,
            DARKNESS_ADD,
            DARKNESS_MAX,
            COUNTER_DOWN_ENTER,
            COUNTER_DOWN_LEAVE,
            MASK_SHADOWED,
        ];
        for (i, state) in counter.iter().enumerate() {
            assert_eq!(state.write_mask, vk::ColorComponentFlags::A, "counter recipe {i}");
        }
        let colour = [COLOUR_REPLACE, MODULATE_BY_DST_ALPHA, MODULATE_BY_SRC_ALPHA, ADD_LIGHT, MODULATE_BY_SRC_COLOUR];
        for (i, state) in colour.iter().enumerate() {
            assert_eq!(blended_alpha(*state, 0.25, 0.75), 0.75, "colour recipe {i} changed alpha");
            assert!(state.write_mask.contains(RGB_ONLY), "colour recipe {i}");
        }
    }

    /// The stencil value left by a ray's volume walls, each at a depth and a front or back
    /// face, over a receiver at depth `receiver` (a wall behind it fails the depth test),
    /// counted from [`STENCIL_COUNT_ZERO`] by `state`.
    fn stencil_after(state: StencilState, walls: &[(f32, bool)], receiver: f32) -> u32 {
        walls.iter().fold(STENCIL_COUNT_ZERO, |value, &(depth, front)| {
            let face = if front { state.front } else { state.back };
            match if depth < receiver { face.pass } else { face.depth_fail } {
                vk::StencilOp::KEEP => value,
                vk::StencilOp::INCREMENT_AND_WRAP => (value + 1) & 0xff,
                vk::StencilOp::DECREMENT_AND_WRAP => value.wrapping_sub(1) & 0xff,
                other => panic!("{other:?} is not modelled"),
            }
        })
    }

    /// Whether `face`'s compare test passes on `value` (reference and value masked).
    fn passes(face: StencilFace, value: u32) -> bool {
        let (reference, value) = (face.reference & face.compare_mask, value & face.compare_mask);
        match face.compare {
            vk::CompareOp::ALWAYS => true,
            vk::CompareOp::LESS => reference < value,
            vk::CompareOp::GREATER_OR_EQUAL => reference >= value,
            vk::CompareOp::EQUAL => reference == value,
            other => panic!("{other:?} is not modelled"),
        }
    }

    #[test]
    fn both_methods_count_the_volumes_a_receiver_is_inside_and_the_tests_read_the_count() {
        // One volume from depth 0.4 (its front wall) to 0.6 (its back wall), and a second
        // around it from 0.2 to 0.8.
        let one = [(0.4, true), (0.6, false)];
        let two = [(0.2, true), (0.4, true), (0.6, false), (0.8, false)];
        for zfail in [false, true] {
            let state = stencil_volume_count(zfail);
            let count = |walls: &[(f32, bool)], receiver| stencil_after(state, walls, receiver) as i32 - 0x80;
            assert_eq!([count(&one, 0.3), count(&one, 0.5), count(&one, 0.7)], [0, 1, 0], "z-fail {zfail}");
            assert_eq!([count(&two, 0.3), count(&two, 0.5), count(&two, 0.9)], [1, 2, 0], "z-fail {zfail}");
        }
        // The apply test passes on a positive count only; the shading test on the others (a
        // negative count is lit).
        for count in -3i32..=3 {
            let value = (0x80 + count) as u32;
            assert_eq!(passes(STENCIL_COUNT_POSITIVE.front, value), count > 0, "{count}");
            assert_eq!(passes(STENCIL_COUNT_NOT_POSITIVE.front, value), count <= 0, "{count}");
        }
    }
}
