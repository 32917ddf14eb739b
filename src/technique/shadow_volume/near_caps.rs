//! Near caps under their own faces (docs/shadow-volumes.md, "Near caps under their faces").
//!
//! In z-pass an open (two-sided) caster keeps a near cap on every face: a view ray may pass a
//! face that the scene pass culled (seen from behind, as through the hole of an open box). Each
//! near cap is its face turned to the light, and the alpha counter draws it twice, once with the
//! pipeline that keeps front faces and once with the one that keeps back faces.
//!
//! Where the scene pass draws the face itself (the same three positions in the same order,
//! through the same invariant vertex stage, culled the same way), the rasteriser covers the
//! same samples with the same depths, and the depth buffer there holds that depth or a nearer
//! one: the near cap's depth test (LESS) fails at every sample it covers. So:
//! - a lit face's near cap is wound as the face: the front-keeping pipeline keeps it exactly
//!   where the scene pass drew the face, and counts nothing; only the back-keeping one needs it;
//! - an unlit face's near cap is the face reversed: the other way round.
//!
//! Each near cap is then drawn by one pipeline, which halves the near caps' vertex and setup work
//! (most of an open assembly's volume triangles) and removes their hidden fragments. A face
//! whose corners welding moved, a masked or blended material (not in the depth buffer whole), a
//! skinned caster (welded corners skinned with their representative's weights) or a mirroring
//! transform keeps its near cap in both.

use ash::vk;

use crate::mesh::VolumeGeometry;

/// Which of the counting pipelines draw a range of a volume's indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DrawnBy {
    /// Every volume pipeline.
    Every,
    /// Only the pipeline that culls back faces (it keeps front faces).
    FrontKeeping,
    /// Only the pipeline that culls front faces.
    BackKeeping,
    /// Only an unculled pipeline (the whole of a split volume at once).
    Unculled,
}

impl DrawnBy {
    /// Whether a pipeline culling `cull` draws this range.
    pub fn draws_with(self, cull: vk::CullModeFlags) -> bool {
        match self {
            DrawnBy::Every => true,
            DrawnBy::FrontKeeping => cull == vk::CullModeFlags::BACK,
            DrawnBy::BackKeeping => cull == vk::CullModeFlags::FRONT,
            DrawnBy::Unculled => cull != vk::CullModeFlags::BACK && cull != vk::CullModeFlags::FRONT,
        }
    }
}

/// Which pipelines can see a face's near cap: its light-facing, and whether the scene pass
/// draws exactly that triangle.
pub fn seen_by(faces_light: bool, as_drawn: bool) -> DrawnBy {
    match (as_drawn, faces_light) {
        (false, _) => DrawnBy::Every,
        (true, true) => DrawnBy::BackKeeping,
        (true, false) => DrawnBy::FrontKeeping,
    }
}

/// How many near caps (triangles) go to each group.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NearCapSplit {
    pub back_only: usize,
    pub both: usize,
    pub front_only: usize,
}

impl NearCapSplit {
    /// Counts the groups of a volume's faces.
    pub fn of(lit_faces: &[bool], faces_as_drawn: &[bool]) -> Self {
        let mut split = NearCapSplit::default();
        for (&lit, &as_drawn) in lit_faces.iter().zip(faces_as_drawn) {
            match seen_by(lit, as_drawn) {
                DrawnBy::BackKeeping => split.back_only += 1,
                DrawnBy::FrontKeeping => split.front_only += 1,
                _ => split.both += 1,
            }
        }
        split
    }

    /// The first and count of each culled pipeline's share of [`NearCapSplit::write_once`]'s
    /// `once` indices, and of an unculled pipeline's (the whole): each one run.
    pub fn once_ranges(&self, once: u32) -> [(u32, u32, DrawnBy); 3] {
        let [back, front] = [self.back_only, self.front_only].map(|n| 3 * n as u32);
        [
            (back, once - back, DrawnBy::FrontKeeping),
            (0, once - front, DrawnBy::BackKeeping),
            (0, once, DrawnBy::Unculled),
        ]
    }

    /// `volume`'s sides, near caps and far cap into `out`, laid out back-only near caps, sides,
    /// near caps for both, far cap, front-only near caps; returns how many indices that is.
    pub fn write_once(&self, volume: &VolumeGeometry, as_drawn: &[bool], out: &mut [u32]) -> usize {
        let [back, both, front] = [self.back_only, self.both, self.front_only].map(|n| 3 * n);
        let (back_out, rest) = out.split_at_mut(back);
        let (sides_out, rest) = rest.split_at_mut(volume.sides.len());
        let (both_out, rest) = rest.split_at_mut(both);
        let (far_out, rest) = rest.split_at_mut(volume.far_cap.len());
        sides_out.copy_from_slice(&volume.sides);
        far_out.copy_from_slice(&volume.far_cap);
        let groups = [back_out, both_out, &mut rest[..front]];
        NearCapSplit::scatter(&volume.near_cap, &volume.lit_faces, as_drawn, groups);
        back + volume.sides.len() + both + volume.far_cap.len() + front
    }

    /// Writes `near_cap` (one triangle per face, in face order) into `back`, `both` and `front`,
    /// each exactly as long as this split says.
    fn scatter(near_cap: &[u32], lit_faces: &[bool], faces_as_drawn: &[bool], [back, both, front]: [&mut [u32]; 3]) {
        let (mut b, mut e, mut f) = (0, 0, 0);
        for ((cap, &lit), &as_drawn) in near_cap.chunks_exact(3).zip(lit_faces).zip(faces_as_drawn) {
            let (out, at) = match seen_by(lit, as_drawn) {
                DrawnBy::BackKeeping => (&mut *back, &mut b),
                DrawnBy::FrontKeeping => (&mut *front, &mut f),
                _ => (&mut *both, &mut e),
            };
            out[*at..*at + 3].copy_from_slice(cap);
            *at += 3;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_face_drawn_as_is_is_seen_by_the_pipeline_its_near_cap_faces_away_from() {
        assert_eq!(seen_by(true, true), DrawnBy::BackKeeping, "a lit face's cap is wound as the face");
        assert_eq!(seen_by(false, true), DrawnBy::FrontKeeping, "an unlit face's cap is reversed");
        assert_eq!(seen_by(true, false), DrawnBy::Every);
        assert_eq!(seen_by(false, false), DrawnBy::Every);
    }

    #[test]
    fn each_range_is_drawn_by_the_pipelines_it_names() {
        let (back, front, none) = (vk::CullModeFlags::BACK, vk::CullModeFlags::FRONT, vk::CullModeFlags::NONE);
        let drawn = |by: DrawnBy| [back, front, none].map(|cull| by.draws_with(cull));
        assert_eq!(drawn(DrawnBy::Every), [true, true, true]);
        assert_eq!(drawn(DrawnBy::FrontKeeping), [true, false, false]);
        assert_eq!(drawn(DrawnBy::BackKeeping), [false, true, false]);
        assert_eq!(drawn(DrawnBy::Unculled), [false, false, true]);
    }

    #[test]
    fn each_culled_pipeline_draws_one_run_of_the_layout() {
        let mut volume = VolumeGeometry::default();
        volume.sides = vec![100, 101, 102];
        volume.near_cap = (0..9).collect();
        volume.far_cap = vec![200, 201, 202];
        volume.lit_faces = vec![true, false, true];
        let as_drawn = [true, true, false];
        let split = NearCapSplit::of(&volume.lit_faces, &as_drawn);
        let mut out = [0; 15];
        assert_eq!(split.write_once(&volume, &as_drawn, &mut out), 15);
        assert_eq!(out, [0, 1, 2, 100, 101, 102, 6, 7, 8, 200, 201, 202, 3, 4, 5]);
        let run = |(first, count, _): (u32, u32, DrawnBy)| out[first as usize..(first + count) as usize].to_vec();
        let [front, back, unculled] = split.once_ranges(15).map(run);
        assert_eq!(front, [100, 101, 102, 6, 7, 8, 200, 201, 202, 3, 4, 5], "sides, both, far, the unlit face");
        assert_eq!(back, [0, 1, 2, 100, 101, 102, 6, 7, 8, 200, 201, 202], "the lit face, sides, both, far");
        assert_eq!(unculled, out);
    }

    #[test]
    fn near_caps_are_scattered_into_their_groups_in_face_order() {
        let near_cap: Vec<u32> = (0..15).collect();
        let lit = [true, false, true, false, true];
        let as_drawn = [true, true, false, true, true];
        let split = NearCapSplit::of(&lit, &as_drawn);
        assert_eq!(split, NearCapSplit { back_only: 2, both: 1, front_only: 2 });
        let (mut back, mut both, mut front) = ([0; 6], [0; 3], [0; 6]);
        NearCapSplit::scatter(&near_cap, &lit, &as_drawn, [&mut back, &mut both, &mut front]);
        assert_eq!(back, [0, 1, 2, 12, 13, 14]);
        assert_eq!(both, [6, 7, 8]);
        assert_eq!(front, [3, 4, 5, 9, 10, 11]);
    }
}
