//! The median of a sample and its percentile-bootstrap confidence interval: resample the values
//! with replacement, take each resample's median, and read the interval off the sorted medians.
//! The resampling draws from a fixed-seed generator, so one set of values always gives the same
//! interval and a report can be reproduced from its rounds.

use serde::Serialize;

/// How an interval is drawn: printed in every report that shows one.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Bootstrap {
    /// Resamples drawn (each as many values as the sample, with replacement).
    pub resamples: u32,
    /// Seed of the resampling generator (SplitMix64).
    pub seed: u64,
    /// Probability mass between the interval's ends.
    pub confidence: f64,
}

impl Bootstrap {
    /// 2000 resamples put the 2.5 % and 97.5 % percentiles 50 medians in from each end: enough
    /// for their position to move by well under the interval's own width between seeds.
    pub const DEFAULT: Bootstrap = Bootstrap { resamples: 2000, seed: 0x6e6f_7374_656e_6369, confidence: 0.95 };

    /// The interval of the median of `values`, or `None` for no values.
    pub fn median_interval(&self, values: &[f64]) -> Option<Interval> {
        if values.is_empty() || self.resamples == 0 {
            return None;
        }
        let mut rng = SplitMix64(self.seed);
        let mut resample = vec![0.0; values.len()];
        let mut medians = Vec::with_capacity(self.resamples as usize);
        for _ in 0..self.resamples {
            for slot in &mut resample {
                *slot = values[rng.below(values.len())];
            }
            resample.sort_by(f64::total_cmp);
            medians.push(median_of_sorted(&resample));
        }
        medians.sort_by(f64::total_cmp);
        let tail = (1.0 - self.confidence) / 2.0;
        let last = medians.len() - 1;
        let low = ((tail * medians.len() as f64).floor() as usize).min(last);
        let high = (((1.0 - tail) * medians.len() as f64).ceil() as usize).saturating_sub(1).clamp(low, last);
        Some(Interval { low: medians[low], high: medians[high] })
    }
}

/// A confidence interval `[low, high]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Interval {
    pub low: f64,
    pub high: f64,
}

impl Interval {
    #[cfg(test)]
    pub fn width(&self) -> f64 {
        self.high - self.low
    }

    #[cfg(test)]
    pub fn contains(&self, value: f64) -> bool {
        self.low <= value && value <= self.high
    }
}

/// The median of `values` (the mean of the two middle ones for an even count), `None` for none.
pub fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    Some(median_of_sorted(&sorted))
}

fn median_of_sorted(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0
    }
}

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny generator whose whole state is its seed, so
/// the interval depends on nothing but the values and `Bootstrap::seed`.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A uniform index in `0..n` (multiply-shift; the bias is below 2^-50 for any sample size
    /// a bench has).
    fn below(&mut self, n: usize) -> usize {
        ((u128::from(self.next()) * n as u128) >> 64) as usize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` values drawn uniformly from [0, 1) by a generator of the test's own (not the one
    /// under test), so the population median is 0.5.
    fn uniform(n: usize, seed: u64) -> Vec<f64> {
        let mut state = seed;
        (0..n)
            .map(|_| {
                // xorshift64*
                state ^= state >> 12;
                state ^= state << 25;
                state ^= state >> 27;
                (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
            })
            .collect()
    }

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(&[]), None);
    }

    #[test]
    fn interval_contains_the_median_and_lies_within_the_data() {
        for n in [1, 2, 5, 12, 40, 101] {
            let values = uniform(n, 7 + n as u64);
            let m = median(&values).unwrap();
            let ci = Bootstrap::DEFAULT.median_interval(&values).unwrap();
            assert!(ci.contains(m), "n = {n}: median {m} outside {ci:?}");
            let (lo, hi) = values.iter().fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
            assert!(lo <= ci.low && ci.high <= hi, "n = {n}: {ci:?} outside the data [{lo}, {hi}]");
        }
    }

    #[test]
    fn constant_values_give_a_point_interval() {
        let ci = Bootstrap::DEFAULT.median_interval(&[1.25; 30]).unwrap();
        assert_eq!(ci, Interval { low: 1.25, high: 1.25 });
    }

    #[test]
    fn interval_narrows_with_more_rounds() {
        // The median's standard error falls as 1/sqrt(n): 16x the values, about a quarter of the
        // width.
        let widths: Vec<f64> = [25, 100, 400]
            .iter()
            .map(|&n| Bootstrap::DEFAULT.median_interval(&uniform(n, 99)).unwrap().width())
            .collect();
        assert!(widths[0] > widths[1] && widths[1] > widths[2], "widths {widths:?}");
        assert!(widths[2] < widths[0] / 2.5, "widths {widths:?}");
    }

    #[test]
    fn the_generator_is_splitmix64_as_published() {
        // The reference outputs for seed 0 (Vigna's splitmix64.c).
        let mut rng = SplitMix64(0);
        let first = [rng.next(), rng.next(), rng.next()];
        assert_eq!(first, [0xe220_a839_7b1d_cdaf, 0x6e78_9e6a_a1b9_65f4, 0x06c4_5d18_8009_454f]);
    }

    #[test]
    fn interval_is_the_seeds_resamples_read_at_the_percentiles() {
        // Worked out apart (the resampling written again in Python): eight resamples of 1..=5
        // have the sorted medians 2, 2, 2, 3, 3, 3, 4, 5 with seed 7 and 2, 2, 2, 3, 3, 3, 4, 4
        // with seed 8; 80 % reads the first and the last of them, 50 % the third and the sixth.
        let values = [1.0, 2.0, 3.0, 4.0, 5.0];
        let at = |seed, confidence| Bootstrap { resamples: 8, seed, confidence }.median_interval(&values);
        assert_eq!(at(7, 0.8), Some(Interval { low: 2.0, high: 5.0 }));
        assert_eq!(at(8, 0.8), Some(Interval { low: 2.0, high: 4.0 }));
        assert_eq!(at(7, 0.5), Some(Interval { low: 2.0, high: 3.0 }));
    }

    #[test]
    fn interval_covers_the_population_median_about_95_percent_of_the_time() {
        // 200 samples of 51 uniform values: the true median 0.5 should fall inside roughly 190 of
        // the intervals (the percentile bootstrap of a median is slightly conservative or
        // slightly liberal depending on n; far from 95 % means the percentiles are misread).
        let bootstrap = Bootstrap { resamples: 1000, ..Bootstrap::DEFAULT };
        let covered =
            (0..200u64).filter(|&s| bootstrap.median_interval(&uniform(51, 1000 + s)).unwrap().contains(0.5)).count();
        assert!((176..=199).contains(&covered), "covered {covered} of 200");
    }

    #[test]
    fn nothing_to_resample_gives_no_interval() {
        assert_eq!(Bootstrap::DEFAULT.median_interval(&[]), None);
        assert_eq!(Bootstrap { resamples: 0, ..Bootstrap::DEFAULT }.median_interval(&[1.0]), None);
    }
}
