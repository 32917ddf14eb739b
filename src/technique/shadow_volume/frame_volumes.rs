//! A caster's volume for one frame, laid out for drawing: which index lists it draws in which
//! order, and in how many ranges (each with its multiplicity and the pipelines that draw it).
//! CPU only, so that the layout can be checked without a GPU; `volume_uploads` writes what it
//! builds into the buffers the renderer draws.

use glam::{Mat4, Vec4};

use super::casters::{build_volume_into, Caster, VolumeScratch};
use super::near_caps::{DrawnBy, NearCapSplit};
use crate::frame::StencilMode;
use crate::mesh::caster::CastPath;
use crate::mesh::{Reach, VolumeGeometry};
use crate::scene::model::AlphaMode;
use crate::scene::{Light, Scene};

/// Indices `first..first + count` of a volume, whose every fragment adds `times` counts: drawn
/// once with `times` k (the alpha counter), or `times` times over (the stencil's +1 ops, for
/// which a volume has one range of every copy).
#[derive(Debug, Clone, Copy)]
pub(super) struct IndexRange {
    pub(super) first: u32,
    pub(super) count: u32,
    pub(super) times: u32,
    /// Which pipelines draw it (a volume whose near caps are split has one range per kind).
    pub(super) drawn_by: DrawnBy,
}

/// How the volumes are counted: the method, and by which counter (the stencil draws repeated
/// walls as copies, the alpha counter once with their multiplicity).
#[derive(Debug, Clone, Copy)]
pub(super) struct Counting {
    pub(super) zfail: bool,
    pub(super) stencil: StencilMode,
    /// Asked for (`--whole-near-caps` not given); done only where `near_caps` says it is exact.
    pub(super) split_near_caps: bool,
}

/// What a volume is built from, beside its caster: equal keys (and an unposed caster) give equal
/// volumes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct VolumeKey {
    pub(super) light: Light,
    pub(super) reach: Reach,
    pub(super) transform: Mat4,
}

/// The volume last written into a caster's buffers for one light, and what it was built from.
pub(super) struct BuiltVolume {
    pub(super) key: VolumeKey,
    pub(super) ranges: Vec<IndexRange>,
}

/// Builds `caster`'s volume for `key` into `scratch` (its vertices where posed on the CPU) and
/// returns its index ranges in draw order (all empty: it casts nothing), with the lists they
/// are written from ([`VolumeIndices::write`]).
pub(super) fn volume_for<'s>(
    scene: &Scene,
    caster: &'s Caster,
    key: VolumeKey,
    counting: Counting,
    scratch: &'s mut VolumeScratch,
) -> VolumeIndices<'s> {
    // Far caps close the volumes (point lights, and every clipped volume): drawn in both
    // methods, so that the background (depth 1) behind a volume never counts. Near caps for
    // z-fail, and for two-sided casters in z-pass too: a ray may pass one of their
    // triangles that the scene pass culled (seen from behind, as through the hole of an
    // open box), so the caster itself does not hide its near cap.
    scratch.volume.indices_only = true;
    build_volume_into(scene, caster, &key.light, key.reach, true, scratch);
    let near_cap = counting.zfail || matches!(caster.mesh.path, CastPath::TwoSided { .. });
    let VolumeScratch { volume, doubled, .. } = scratch;
    if !near_cap {
        volume.near_cap.clear();
    }
    // A mirroring transform (negative determinant) flips every winding on screen: turn
    // the triangles back so that the volume's faces still point out.
    if key.transform.determinant() < 0.0 {
        let lists = [&mut volume.sides, &mut volume.near_cap, &mut volume.far_cap].into_iter();
        for list in lists.chain(volume.repeated_walls.iter_mut().map(|(_, walls)| walls)) {
            list.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
        }
    }
    let once = (volume.sides.len() + volume.near_cap.len() + volume.far_cap.len()) as u32;
    let split = near_caps_split(scene, caster, key, counting).map(|as_drawn| {
        let lit = &volume.lit_faces;
        (NearCapSplit::of(lit, as_drawn), as_drawn)
    });
    let mut ranges = match split {
        None => vec![IndexRange { first: 0, count: once, times: 1, drawn_by: DrawnBy::Every }],
        // Laid out so that each culled pipeline's share is one run (`NearCapSplit::write_once`).
        Some((groups, _)) => {
            let ranges = groups.once_ranges(once).into_iter();
            ranges.map(|(first, count, drawn_by)| IndexRange { first, count, times: 1, drawn_by }).collect()
        }
    };
    let mut end = once;
    match counting.stencil {
        // The stencil's ops add 1 a fragment: a repeated list is drawn `times` times over.
        StencilMode::Reference => {
            end += volume.repeated_walls.iter().map(|(times, walls)| times * walls.len() as u32).sum::<u32>();
            ranges = vec![IndexRange { first: 0, count: end, times: 1, drawn_by: DrawnBy::Every }];
        }
        // The alpha counter draws it once, adding `times` k.
        StencilMode::Emulated => {
            for (times, walls) in &volume.repeated_walls {
                let count = walls.len() as u32;
                ranges.push(IndexRange { first: end, count, times: *times, drawn_by: DrawnBy::Every });
                end += walls.len() as u32;
            }
        }
    }
    VolumeIndices {
        volume,
        volume_vertices: doubled,
        ranges,
        len: end as usize,
        stencil: counting.stencil,
        near_caps: split,
    }
}

/// Where `caster`'s near caps may each be left to the one pipeline that can see them
/// (`near_caps`), its faces drawn as the scene pass draws them; `None` where all are drawn by
/// both: z-fail, the stencil, a closed caster (no near caps in z-pass), a skinned or mirrored
/// one, or a material the depth buffer does not hold whole.
fn near_caps_split<'c>(scene: &Scene, caster: &'c Caster, key: VolumeKey, counting: Counting) -> Option<&'c [bool]> {
    let object = &scene.objects[caster.object];
    let opaque = matches!(scene.material_of(object).alpha_mode, AlphaMode::Opaque);
    let eligible = counting.split_near_caps
        && !counting.zfail
        && counting.stencil == StencilMode::Emulated
        && matches!(caster.mesh.path, CastPath::TwoSided { .. })
        && object.skin.is_none()
        && key.transform.determinant() > 0.0
        && opaque;
    eligible.then_some(caster.mesh.faces_as_drawn.as_slice())
}

/// A volume built in a scratch, its ranges, and how many indices they hold.
pub(super) struct VolumeIndices<'s> {
    pub(super) volume: &'s VolumeGeometry,
    /// A caster posed on the CPU: its posed vertices, doubled (else empty).
    pub(super) volume_vertices: &'s [Vec4],
    pub(super) ranges: Vec<IndexRange>,
    pub(super) len: usize,
    /// Which counter the ranges were laid out for.
    pub(super) stencil: StencilMode,
    /// Near caps split by the pipelines that see them: the groups, and which faces the scene
    /// pass draws as they are.
    pub(super) near_caps: Option<(NearCapSplit, &'s [bool])>,
}

impl VolumeIndices<'_> {
    /// The indices in draw order into `out` (`len` long): sides, caps, then the repeated
    /// walls (once each for the alpha counter, `times` times over for the stencil).
    pub(super) fn write(&self, out: &mut [u32]) {
        let volume = self.volume;
        let mut at = 0;
        let once: [&[u32]; 3] = match self.near_caps {
            None => [&volume.sides, &volume.near_cap, &volume.far_cap],
            Some((groups, as_drawn)) => {
                at = groups.write_once(volume, as_drawn, out);
                [&[]; 3]
            }
        };
        let repeated = volume.repeated_walls.iter().flat_map(|(times, walls)| {
            let times = if self.stencil == StencilMode::Reference { *times as usize } else { 1 };
            std::iter::repeat(walls.as_slice()).take(times)
        });
        for list in once.into_iter().chain(repeated) {
            out[at..at + list.len()].copy_from_slice(list);
            at += list.len();
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::scene::builtin_scene;
    use crate::technique::shadow_volume::casters::prepare_casters;

    /// Every caster's layout in `scene_name` under its first light, as `volume_for` lays it out
    /// for `counting` (the transform in the key mirrored where `mirror`): the volume's lists,
    /// the ranges, and the indices written.
    fn layouts(scene_name: &str, counting: Counting, mirror: bool) -> Vec<(VolumeGeometry, Vec<IndexRange>, Vec<u32>)> {
        let scene = builtin_scene(scene_name).expect("scene");
        let (casters, _) = prepare_casters(&scene);
        assert!(!casters.is_empty(), "{scene_name} has casters");
        let light = scene.lights[0].geometry();
        casters
            .iter()
            .map(|caster| {
                let flip = if mirror { Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) } else { Mat4::IDENTITY };
                let transform = scene.objects[caster.object].transform * flip;
                let key = VolumeKey { light, reach: Reach::Infinite, transform };
                let mut scratch = VolumeScratch::default();
                let built = volume_for(&scene, caster, key, counting, &mut scratch);
                let mut out = vec![u32::MAX; built.len];
                built.write(&mut out);
                (built.volume.clone(), built.ranges, out)
            })
            .collect()
    }

    fn counting(zfail: bool, stencil: StencilMode) -> Counting {
        Counting { zfail, stencil, split_near_caps: false }
    }

    #[test]
    fn the_alpha_counter_draws_each_list_once_and_the_repeated_walls_with_their_multiplicity() {
        let mut repeated = 0;
        for (volume, ranges, written) in layouts("non-manifold", counting(true, StencilMode::Emulated), false) {
            let once = volume.sides.len() + volume.near_cap.len() + volume.far_cap.len();
            let mut expected: Vec<u32> = [volume.sides.as_slice(), &volume.near_cap, &volume.far_cap].concat();
            let mut wanted = vec![(0, once as u32, 1)];
            for (times, walls) in &volume.repeated_walls {
                wanted.push((expected.len() as u32, walls.len() as u32, *times));
                expected.extend(walls);
                repeated += usize::from(*times >= 2);
            }
            let got: Vec<_> = ranges.iter().map(|r| (r.first, r.count, r.times)).collect();
            assert_eq!(got, wanted);
            assert_eq!(written, expected);
        }
        assert!(repeated > 0, "the non-manifold scene has walls drawn more than once");
    }

    #[test]
    fn the_stencil_draws_one_range_with_each_repeated_wall_copied() {
        for (volume, ranges, written) in layouts("non-manifold", counting(true, StencilMode::Reference), false) {
            let mut expected: Vec<u32> = [volume.sides.as_slice(), &volume.near_cap, &volume.far_cap].concat();
            for (times, walls) in &volume.repeated_walls {
                for _ in 0..*times {
                    expected.extend(walls);
                }
            }
            let got: Vec<_> = ranges.iter().map(|r| (r.first, r.count, r.times)).collect();
            assert_eq!(got, [(0, expected.len() as u32, 1)]);
            assert_eq!(written, expected);
        }
    }

    #[test]
    fn z_pass_leaves_a_closed_casters_near_cap_out() {
        let zfail = layouts("box", counting(true, StencilMode::Emulated), false);
        let zpass = layouts("box", counting(false, StencilMode::Emulated), false);
        for ((fail, _, fail_written), (pass, _, pass_written)) in zfail.iter().zip(&zpass) {
            assert!(!fail.near_cap.is_empty());
            assert!(pass.near_cap.is_empty());
            assert_eq!(pass_written.len(), fail_written.len() - fail.near_cap.len());
        }
    }

    #[test]
    fn a_mirroring_transform_turns_every_triangle_back() {
        let plain = layouts("non-manifold", counting(true, StencilMode::Reference), false);
        let mirrored = layouts("non-manifold", counting(true, StencilMode::Reference), true);
        for ((_, _, plain), (_, _, mirrored)) in plain.iter().zip(&mirrored) {
            let turned: Vec<u32> = plain.chunks_exact(3).flat_map(|t| [t[0], t[2], t[1]]).collect();
            assert_eq!(*mirrored, turned);
        }
    }
}
