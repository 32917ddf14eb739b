//! The alpha channel as an 8-bit counter (docs/design/alpha-counter.md, shadow-volumes.md,
//! blend-rounding.md): the blend arithmetic
//! of the seed's normalisation passes, simulated on the CPU under every rounding Vulkan allows,
//! so that the number of iterations is derived from the increment k and the darkness D, never
//! hard-coded.

use crate::error::{Error, Result};

/// Largest increment the renderer accepts (`--increment 1..8`).
pub const MAX_INCREMENT: u8 = 8;

/// More iterations than any k and D need (5 at most): a bound for the search, not a count.
const ITERATION_BOUND: usize = 16;

/// The largest volume count the counter holds with increment k: 255 / k.
pub fn capacity(k: u8) -> u32 {
    255 / k.max(1) as u32
}

pub fn check_increment(k: u8) -> Result<u8> {
    if (1..=MAX_INCREMENT).contains(&k) {
        Ok(k)
    } else {
        Err(Error::InvalidInput(format!("--increment {k}: must be 1 to {MAX_INCREMENT}")))
    }
}

crate::names::named_enum! {
    /// How a GPU turns a blend product `a * b / 255` into 8 bits. Vulkan allows either
    /// neighbour of the exact value (an exact integer exactly), so a port must hold under
    /// `down` and `up`; `nearest` is what the specification recommends, `lavapipe` what the
    /// test device does (docs/design/lavapipe.md).
    pub enum Rounding {
        #[default]
        Nearest = "nearest",
        Down = "down",
        Up = "up",
        Lavapipe = "lavapipe",
    }
}

impl Rounding {
    /// `a * b / 255` in 8 bits under this rounding.
    pub fn product(self, a: u8, b: u8) -> u8 {
        let p = a as u32 * b as u32;
        let rounded = match self {
            // No product lies half-way: 2p = 255 (2m + 1) has no integer solution.
            Rounding::Nearest => (2 * p + 255) / 510,
            Rounding::Down => p / 255,
            Rounding::Up => p.div_ceil(255),
            Rounding::Lavapipe => (p + (p >> 8) + 128) >> 8,
        };
        rounded as u8
    }
}

/// One full-screen normalisation pass of the seed and max paths, as blend arithmetic on the
/// destination alpha (fragment alpha 1 for N0 and the iterations, D for the darkness steps).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Step {
    /// `SUBTRACT, Sf = ONE_MINUS_DST_ALPHA, Df = ONE`: `1 - 2a` (exact: `1 - a` is exact).
    N0,
    /// `REVERSE_SUBTRACT, Sf = ONE_MINUS_DST_ALPHA, Df = DST_ALPHA`: `a * a - (1 - a)`.
    Iteration,
    // The darkness steps model the rest of the seed's pass list, which the tests run on the
    // CPU (tests/inside/shadow_volume/counter.rs applies them with a D); the renderer only
    // counts the iterations here: outside the tests they are never built.
    /// `REVERSE_SUBTRACT, ONE, ONE` of D.
    #[cfg_attr(not(test), allow(dead_code))]
    SubtractD,
    /// `ADD, ONE, ONE` of D.
    #[cfg_attr(not(test), allow(dead_code))]
    AddD,
    /// `MAX` with D.
    #[cfg_attr(not(test), allow(dead_code))]
    MaxD,
}

impl Step {
    /// The destination alpha after this pass, with products rounded by `rounding`.
    pub fn apply(self, a: u8, darkness: u8, rounding: Rounding) -> u8 {
        // Sf = 1 - a times a source of 1: a product by 255, exact in every rounding.
        let one_minus_a = rounding.product(255, 255 - a) as i32;
        let a_i = a as i32;
        let value = match self {
            Step::N0 => one_minus_a - a_i,
            Step::Iteration => rounding.product(a, a) as i32 - one_minus_a,
            Step::SubtractD => a_i - darkness as i32,
            Step::AddD => a_i + darkness as i32,
            Step::MaxD => a_i.max(darkness as i32),
        };
        value.clamp(0, 255) as u8
    }
}

/// Seed 000's own table of a shadowed pixel's alpha through the normalisation, as printed in
/// Brian Hall, "Creating Stencil Shadows on iPhone" (Gamasutra, 16 June 2010; its Korean
/// translation's table "단계 / 알파 값", see `docs/sources.md`): the
/// initial count of one wall at 1/256, then after N0 ("단계 1") and four iterations ("단계
/// 2..5"), four decimals. Lit pixels read 0 then 1 throughout.
#[cfg(test)]
pub const SEED_TABLE: [f64; 6] = [0.0040, 0.9922, 0.9767, 0.9306, 0.7966, 0.4312];

/// The alpha values a count goes through under lavapipe's rounding: after N0, then after each
/// iteration until 0 (or 1, which stays).
#[cfg(test)]
pub fn seed_sequence(count_alpha: u8) -> Vec<u8> {
    let mut values = vec![Step::N0.apply(count_alpha, 0, Rounding::Lavapipe)];
    while let Some(&last) = values.last() {
        if last == 0 || last == 255 || values.len() > ITERATION_BOUND {
            break;
        }
        values.push(Step::Iteration.apply(last, 0, Rounding::Lavapipe));
    }
    values
}

/// The alpha of every shadowed count (k, 2k, ... up to 255 / k volumes) after N0 and
/// `iterations` iterations under `rounding`.
pub fn shadowed_after(k: u8, iterations: usize, rounding: Rounding) -> impl Iterator<Item = u8> {
    (1..=capacity(k)).map(move |count| {
        let mut a = Step::N0.apply((count * k as u32) as u8, 0, rounding);
        for _ in 0..iterations {
            a = Step::Iteration.apply(a, 0, rounding);
        }
        a
    })
}

/// Iterations after N0 that a port can trust (docs/design/blend-rounding.md): the smallest n that brings
/// every shadowed count to <= D when every product rounds up (the worst case: the iteration is
/// increasing in `a`), so that the D step (`-D, +D` or `MAX D`) sets it to exactly D. A count
/// of 0 goes to 1 and stays there in every rounding.
pub fn seed_iterations(k: u8, darkness: u8) -> Result<usize> {
    let k = check_increment(k)?;
    let lit_stays_lit = Rounding::ALL.iter().all(|&r| {
        let lit = Step::N0.apply(0, darkness, r);
        lit == 255 && Step::Iteration.apply(lit, darkness, r) == 255
    });
    if !lit_stays_lit {
        return Err(Error::Internal("normalisation does not keep unshadowed pixels at 1".into()));
    }
    (0..=ITERATION_BOUND)
        .find(|&n| shadowed_after(k, n, Rounding::Up).all(|a| a <= darkness))
        .ok_or_else(|| Error::Internal(format!("k = {k}, D = {darkness}: shadowed counts never reach D")))
}

/// The additive mode's iterations (docs/shadow-volumes.md, "Several lights"): its counter
/// counts down from 1 (255 - count x k), so no N0 is needed (1 is the iteration's fixed
/// point), and the smallest n that brings every shadowed count to exactly 0 when every product
/// rounds up (the worst case) makes a mask of exactly {0, 1} on any conforming GPU.
pub fn down_iterations(k: u8) -> Result<usize> {
    let k = check_increment(k)?;
    let lit_stays_lit = Rounding::ALL.iter().all(|&r| Step::Iteration.apply(255, 0, r) == 255);
    if !lit_stays_lit {
        return Err(Error::Internal("the iteration does not keep a count of 0 at 1".into()));
    }
    (0..=ITERATION_BOUND)
        .find(|&n| down_counts_after(k, n, Rounding::Up).all(|a| a == 0))
        .ok_or_else(|| Error::Internal(format!("k = {k}: shadowed down-counts never reach 0")))
}

/// The alpha of every shadowed down-count (255 - k, 255 - 2k, ... down to the clamp at 0)
/// after `iterations` iterations under `rounding`.
pub fn down_counts_after(k: u8, iterations: usize, rounding: Rounding) -> impl Iterator<Item = u8> {
    (1..=capacity(k)).map(move |count| {
        let mut a = 255u32.saturating_sub(count * k as u32) as u8;
        for _ in 0..iterations {
            a = Step::Iteration.apply(a, 0, rounding);
        }
        a
    })
}

/// The iteration counts for each D (rows) and k (columns), as a Markdown table: what the
/// docs/shadow-volumes.md prints and `nostencil passes --technique shadow-volume` shows.
pub fn iteration_table(darkness: &[u8], increments: &[u8]) -> Result<String> {
    let header: Vec<String> = increments.iter().map(|k| format!("k = {k}")).collect();
    let mut table = format!("| D | {} |\n|---|{}\n", header.join(" | "), "---|".repeat(increments.len()));
    for &d in darkness {
        let counts = increments.iter().map(|&k| seed_iterations(k, d).map(|n| n.to_string()));
        table.push_str(&format!("| {d} | {} |\n", counts.collect::<Result<Vec<_>>>()?.join(" | ")));
    }
    Ok(table)
}

/// The rows and columns of the table docs/shadow-volumes.md prints.
pub const TABLE_DARKNESS: [u8; 6] = [0, 32, 64, 102, 128, 192];
pub const TABLE_INCREMENTS: [u8; 4] = [1, 2, 4, 8];

/// The iteration table with its heading: what `nostencil passes --technique shadow-volume`
/// prints after the plans, and docs/shadow-volumes.md's copy of it (checked by a test).
pub fn iteration_section() -> Result<String> {
    Ok(format!(
        "Iterations after N0 (`seed`, `max`) for shadow factor D and increment k: the smallest n\n\
         that brings every shadowed count to <= D when every blend product rounds up.\n\n{}",
        iteration_table(&TABLE_DARKNESS, &TABLE_INCREMENTS)?
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn count_of_one_follows_the_design_table() {
        // docs/design/lavapipe.md: 1 -> 253 -> 249 -> 237 -> 202 -> 107 -> 0.
        assert_eq!(seed_sequence(1), vec![253, 249, 237, 202, 107, 0]);
    }

    /// The seed's table is the iteration `a * a - (1 - a)` carried out in real numbers and
    /// printed to four decimals at each step: every row is the recurrence of the row before
    /// (N0, `1 - 2a`, of the initial 1/256, printed as 0.0040 rounded up from 0.0039).
    #[test]
    fn the_seeds_table_is_the_real_number_recurrence() {
        assert!((1.0 - 2.0 / 256.0 - SEED_TABLE[1]).abs() < 5e-5);
        for step in 2..SEED_TABLE.len() {
            let a = SEED_TABLE[step - 1];
            let next = a * a - (1.0 - a);
            assert!((next - SEED_TABLE[step]).abs() < 5e-5, "step {step}: {next:.5} against {}", SEED_TABLE[step]);
        }
    }

    /// How close 8 bits come to the seed's real numbers: the same steps, each product rounded to
    /// 1/255 (lavapipe's rounding, and to nearest), stay within 0.012 of the table at step 5 and
    /// drift apart at every step. Why: the iteration's slope `2a + 1` is about 3 near a = 1,
    /// so each step roughly triples the gap that rounding a product to 8 bits (and starting
    /// from 1/255 rather than 1/256) left the step before.
    #[test]
    fn eight_bit_steps_stay_within_0_012_of_the_seeds_table() {
        for rounding in [Rounding::Lavapipe, Rounding::Nearest] {
            let mut a = Step::N0.apply(1, 0, rounding);
            let mut gaps = vec![(f64::from(a) / 255.0 - SEED_TABLE[1]).abs()];
            for &seed in &SEED_TABLE[2..] {
                a = Step::Iteration.apply(a, 0, rounding);
                gaps.push((f64::from(a) / 255.0 - seed).abs());
            }
            let last = gaps[gaps.len() - 1];
            assert!(last <= 0.012, "{rounding:?}: step 5 is {last:.4} from the seed's 0.4312 ({gaps:?})");
            assert!(last > 0.005, "{rounding:?}: the gap at step 5 is real ({last:.4})");
            for pair in gaps[1..].windows(2) {
                assert!(pair[1] > pair[0], "{rounding:?}: the gap grows step by step ({gaps:?})");
            }
        }
    }

    #[test]
    fn iterations_follow_the_design_table() {
        // docs/design/blend-rounding.md, counted by hand with products rounded up.
        for (d, counts) in [(102u8, [5usize, 4, 3, 3]), (128, [5, 4, 3, 2]), (64, [5, 4, 4, 3])] {
            for (k, n) in [1u8, 2, 4, 8].into_iter().zip(counts) {
                assert_eq!(seed_iterations(k, d).unwrap(), n, "k = {k}, D = {d}");
            }
        }
        assert!(seed_iterations(0, 102).is_err());
        assert!(seed_iterations(9, 102).is_err());
    }

    /// Every k in 1..=8 and D in 1..=254, under every rounding: the derived n brings every
    /// shadowed count to <= D and leaves lit pixels at 255, and one iteration fewer fails when
    /// products round up.
    #[test]
    fn derived_iterations_hold_under_every_rounding() {
        for k in 1..=MAX_INCREMENT {
            for d in 1..=254u8 {
                let n = seed_iterations(k, d).unwrap();
                for rounding in Rounding::ALL.iter().copied() {
                    let worst = shadowed_after(k, n, rounding).max().unwrap();
                    assert!(worst <= d, "k = {k}, D = {d}, {rounding:?}: a shadowed pixel ends at {worst}");
                    let mut lit = Step::N0.apply(0, d, rounding);
                    for _ in 0..n {
                        lit = Step::Iteration.apply(lit, d, rounding);
                    }
                    assert_eq!(lit, 255, "k = {k}, D = {d}, {rounding:?}: a lit pixel");
                    // The D steps then give exactly D and 255.
                    for a in shadowed_after(k, n, rounding) {
                        assert_eq!(Step::AddD.apply(Step::SubtractD.apply(a, d, rounding), d, rounding), d);
                        assert_eq!(Step::MaxD.apply(a, d, rounding), d);
                    }
                    assert_eq!(Step::AddD.apply(Step::SubtractD.apply(255, d, rounding), d, rounding), 255);
                    assert_eq!(Step::MaxD.apply(255, d, rounding), 255);
                }
                // A count of k leaves N0 at 255 - 2k: from D >= that on, no iteration is needed.
                if d < 255 - 2 * k {
                    assert!(n > 0, "k = {k}, D = {d}");
                    let worst = shadowed_after(k, n - 1, Rounding::Up).max().unwrap();
                    assert!(worst > d, "k = {k}, D = {d}: {} iteration(s) already suffice", n - 1);
                } else {
                    assert_eq!(n, 0, "k = {k}, D = {d}");
                }
            }
        }
    }

    #[test]
    fn rounding_up_bounds_every_other_rounding() {
        for a in 0..=255u8 {
            for b in 0..=255u8 {
                let exact = a as f64 * b as f64 / 255.0;
                let up = Rounding::Up.product(a, b);
                for rounding in Rounding::ALL.iter().copied() {
                    let p = rounding.product(a, b);
                    assert!((p as f64 - exact).abs() < 1.0, "{rounding:?}: {a} x {b} -> {p}, exact {exact}");
                    assert!(p <= up);
                }
                assert_eq!(Rounding::Down.product(a, b) as f64, exact.floor());
                assert_eq!(Rounding::Up.product(a, b) as f64, exact.ceil());
                assert_eq!(Rounding::Nearest.product(a, b) as f64, exact.round());
            }
        }
        for rounding in Rounding::ALL.iter().copied() {
            assert!((0..=255u8).all(|a| rounding.product(a, 255) == a));
        }
    }

    #[test]
    fn the_table_has_a_row_per_darkness() {
        let table = iteration_table(&[102], &[1, 4]).unwrap();
        assert_eq!(table, "| D | k = 1 | k = 4 |\n|---|---|---|\n| 102 | 5 | 3 |\n");
    }

    #[test]
    fn the_readme_prints_the_iteration_table() {
        let readme = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/shadow-volumes.md"));
        let section = iteration_section().unwrap();
        assert!(readme.contains(&section), "docs/shadow-volumes.md's iteration table differs; paste:\n{section}");
    }

    #[test]
    fn down_counts_reach_zero_in_the_derived_iterations_and_not_one_sooner() {
        let derived: Vec<usize> = TABLE_INCREMENTS.iter().map(|&k| down_iterations(k).expect("k")).collect();
        assert_eq!(derived, [6, 5, 5, 4]);
        for (&k, &n) in TABLE_INCREMENTS.iter().zip(&derived) {
            for rounding in Rounding::ALL.iter().copied() {
                assert!(down_counts_after(k, n, rounding).all(|a| a == 0), "k = {k}, {rounding:?}");
            }
            assert!(down_counts_after(k, n - 1, Rounding::Up).any(|a| a > 0), "k = {k}: n - 1 would do");
            // A count of 0 (alpha 1) is the iteration's fixed point: lit stays exactly lit.
            let mut lit = 255;
            for _ in 0..n {
                lit = Step::Iteration.apply(lit, 0, Rounding::Up);
            }
            assert_eq!(lit, 255);
        }
    }

    #[test]
    fn capacity_is_255_over_k() {
        assert_eq!(capacity(1), 255);
        assert_eq!(capacity(2), 127);
        assert_eq!(capacity(8), 31);
    }
}
