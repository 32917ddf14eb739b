//! `--tour N`: the soak's script. Every N presented frames the viewer moves to the next stop
//! of a tour through every technique, in both stencil modes, at 1 and 4 samples, the window
//! resized at every stop between its size and a smaller one. At the end of each full tour it
//! prints the process's resident memory and the Vulkan objects alive: a leak shows as growth
//! from one tour to the next.

use crate::frame::StencilMode;
use crate::gpu::Gpu;
use crate::technique::{RenderOptions, TECHNIQUES};

/// The sample counts a tour visits (a count the device lacks for the frame is replaced by 1).
const TOUR_SAMPLES: [u32; 2] = [1, 4];
const TOUR_STENCILS: [StencilMode; 2] = [StencilMode::Emulated, StencilMode::Reference];

/// One stop: what the frames show and the window size they are drawn at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stop {
    pub technique: usize,
    pub stencil: StencilMode,
    pub samples: u32,
    pub size: (u32, u32),
}

pub struct Tour {
    every: u32,
    stops: Vec<Stop>,
}

impl Tour {
    /// A tour changing stop every `every` frames (at least 1), resizing between `size` and
    /// about 5/6 of it.
    pub fn new(every: u32, size: (u32, u32)) -> Self {
        let smaller = ((size.0 * 5 / 6).max(1), (size.1 * 5 / 6).max(1));
        let mut stops = Vec::new();
        for samples in TOUR_SAMPLES {
            for stencil in TOUR_STENCILS {
                for technique in 0..TECHNIQUES.len() {
                    let size = if stops.len() % 2 == 0 { size } else { smaller };
                    stops.push(Stop { technique, stencil, samples, size });
                }
            }
        }
        Tour { every: every.max(1), stops }
    }

    /// Frames in one full tour.
    #[cfg(test)]
    pub fn frames_per_tour(&self) -> u32 {
        self.every * self.stops.len() as u32
    }

    /// After `presented` frames: the stop the next frame belongs to when it is a new one, and
    /// the number of tours just completed when one just was.
    pub fn at(&self, presented: u32) -> (Option<Stop>, Option<u32>) {
        if presented % self.every != 0 {
            return (None, None);
        }
        let index = (presented / self.every) as usize;
        let completed = (index > 0 && index % self.stops.len() == 0).then(|| (index / self.stops.len()) as u32);
        (Some(self.stops[index % self.stops.len()]), completed)
    }
}

impl Stop {
    /// Sets the frame options of this stop (4 samples only where the device offers them).
    pub fn apply(&self, gpu: &Gpu, render: &mut RenderOptions) {
        render.technique = TECHNIQUES[self.technique];
        render.stencil = self.stencil;
        render.samples = self.samples;
        if crate::frame::targets::check_samples(gpu, render.stencil, render.samples).is_err() {
            render.samples = 1;
        }
    }
}

/// The process's resident memory in KiB (VmRSS of /proc/self/status), where the system says.
pub fn resident_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tour_visits_every_technique_stencil_and_sample_count_with_resizes() {
        let tour = Tour::new(3, (96, 72));
        assert_eq!(tour.frames_per_tour(), 3 * 4 * TECHNIQUES.len() as u32);
        let mut seen = Vec::new();
        let mut completed = Vec::new();
        for presented in 0..2 * tour.frames_per_tour() + 1 {
            let (stop, done) = tour.at(presented);
            assert_eq!(stop.is_some(), presented % 3 == 0, "frame {presented}");
            seen.extend(stop.filter(|_| presented < tour.frames_per_tour()));
            completed.extend(done.map(|n| (presented, n)));
        }
        assert_eq!(completed, [(tour.frames_per_tour(), 1), (2 * tour.frames_per_tour(), 2)]);
        for technique in 0..TECHNIQUES.len() {
            for stencil in TOUR_STENCILS {
                for samples in TOUR_SAMPLES {
                    let stops =
                        seen.iter().filter(|s| (s.technique, s.stencil, s.samples) == (technique, stencil, samples));
                    assert_eq!(stops.count(), 1, "{technique} {stencil:?} {samples}");
                }
            }
        }
        // Consecutive stops differ in size: each one resizes the window.
        assert!(seen.windows(2).all(|w| w[0].size != w[1].size));
        assert!(seen.iter().any(|s| s.size == (80, 60)));
    }

    #[test]
    fn resident_memory_is_read_on_linux() {
        if cfg!(target_os = "linux") {
            assert!(resident_kib().is_some_and(|kib| kib > 0));
        }
    }
}
