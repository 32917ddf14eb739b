//! Skins: joints and inverse bind matrices, the per-vertex influences (JOINTS_n/WEIGHTS_n)
//! reduced to four and renormalised, and joint indices checked against the skin each mesh is
//! drawn with.

use glam::Mat4;
use gltf::json;
use json::accessor::{ComponentType as C, Type as T};

use super::loader::{label, Loader, FLOAT_OR_UNORM};
use crate::error::{Error, Result};
use crate::scene::model::{Mesh, Node, Skin, MAX_JOINTS};

/// JOINTS_0 and WEIGHTS_0 of one primitive.
type SkinAttributes = (Vec<[u16; 4]>, Vec<[f32; 4]>);

impl Loader<'_> {
    /// One JOINTS_k/WEIGHTS_k pair: `n` vertices of four (joint, weight) influences.
    fn influence_set(
        &self,
        what: &str,
        set: usize,
        (joints, weights): (usize, usize),
        n: usize,
    ) -> Result<SkinAttributes> {
        let name = format!("{what} JOINTS_{set}");
        let raw = self.accessor(joints, &name, &[T::Vec4], &[C::U8, C::U16])?.uints();
        let joints: Vec<[u16; 4]> =
            raw.chunks_exact(4).map(|j| [j[0] as u16, j[1] as u16, j[2] as u16, j[3] as u16]).collect();
        if joints.len() != n {
            return Err(self.fail(format!("{name} has {} elements but POSITION has {n}", joints.len())));
        }
        let name = format!("{what} WEIGHTS_{set}");
        let flat = self.floats(weights, &name, T::Vec4, FLOAT_OR_UNORM)?;
        let weights: Vec<[f32; 4]> = flat.chunks_exact(4).map(|w| [w[0], w[1], w[2], w[3]]).collect();
        if weights.len() != n {
            return Err(self.fail(format!("{name} has {} elements but POSITION has {n}", weights.len())));
        }
        if let Some((v, w)) = weights.iter().enumerate().find(|(_, w)| w.iter().any(|x| !x.is_finite() || *x < -1e-6)) {
            return Err(
                self.fail(format!("{name}: vertex {v} has weights {w:?}; weights must be finite and not negative"))
            );
        }
        Ok((joints, weights))
    }

    /// Four influences per vertex, as the GPU skins them: with more sets than one, the four
    /// strongest of all; then weights renormalised to sum to 1 (exporters round them, or drop
    /// the influences past four without renormalising).
    pub(super) fn skin_attributes(&mut self, what: &str, sets: &[(usize, usize)], n: usize) -> Result<SkinAttributes> {
        let mut read = Vec::with_capacity(sets.len());
        for (set, pair) in sets.iter().enumerate() {
            read.push(self.influence_set(what, set, *pair, n)?);
        }
        let mut joints = Vec::with_capacity(n);
        let mut weights = Vec::with_capacity(n);
        let mut dropped = 0usize;
        let mut all = Vec::with_capacity(4 * sets.len());
        for v in 0..n {
            all.clear();
            for (j, w) in &read {
                all.extend(j[v].iter().zip(&w[v]).map(|(j, w)| (*j, w.max(0.0))));
            }
            if all.len() > 4 {
                // Stable: equal weights keep the file's order.
                all.sort_by(|a, b| b.1.total_cmp(&a.1));
                dropped += all[4..].iter().any(|(_, w)| *w > 0.0) as usize;
            }
            joints.push([0, 1, 2, 3].map(|k| all[k].0));
            weights.push([0, 1, 2, 3].map(|k| all[k].1));
        }
        let name = format!("{what} WEIGHTS_0");
        if dropped > 0 {
            self.warnings.push(format!(
                "{name}..{}: {dropped} vertices have more than 4 influences; the 4 strongest are kept",
                sets.len() - 1
            ));
        }
        let mut unweighted = 0usize;
        let mut renormalised = 0usize;
        for w in weights.iter_mut() {
            let sum: f32 = w.iter().sum();
            if sum <= 0.0 {
                *w = [1.0, 0.0, 0.0, 0.0];
                unweighted += 1;
            } else {
                if (sum - 1.0).abs() > 1e-3 {
                    renormalised += 1;
                }
                for x in w.iter_mut() {
                    *x /= sum;
                }
            }
        }
        if unweighted > 0 {
            self.warnings
                .push(format!("{name}: {unweighted} vertices have all-zero weights; bound to their first joint"));
        }
        if renormalised > 0 {
            self.warnings.push(format!("{name}: {renormalised} vertices had weights not summing to 1; renormalised"));
        }
        Ok((joints, weights))
    }

    pub(super) fn skins(&mut self) -> Result<Vec<Skin>> {
        let mut out = Vec::with_capacity(self.root.skins.len());
        for (s, skin) in self.root.skins.iter().enumerate() {
            let what = label("skin", s, skin.name.as_deref());
            let joints: Vec<usize> = skin.joints.iter().map(|j| j.value()).collect();
            if joints.is_empty() {
                return Err(self.fail(format!("{what} has no joints")));
            }
            if joints.len() > MAX_JOINTS {
                return Err(self.fail(format!(
                    "{what} has {} joints; at most {MAX_JOINTS} are supported (the joint \
                     matrices live in a {} KiB uniform buffer)",
                    joints.len(),
                    MAX_JOINTS * 64 / 1024
                )));
            }
            if let Some(j) = joints.iter().find(|&&j| j >= self.root.nodes.len()) {
                return Err(self.fail(format!("{what}: joint node {j} does not exist")));
            }
            let inverse_bind = match skin.inverse_bind_matrices {
                Some(i) => {
                    let name = format!("{what} inverseBindMatrices");
                    let flat = self.floats(i.value(), &name, T::Mat4, &[C::F32])?;
                    let matrices: Vec<Mat4> = flat.chunks_exact(16).map(Mat4::from_cols_slice).collect();
                    if matrices.len() < joints.len() {
                        return Err(self.fail(format!(
                            "{name} has {} matrices for {} joints",
                            matrices.len(),
                            joints.len()
                        )));
                    }
                    if let Some(k) = matrices.iter().position(|m| !m.is_finite()) {
                        return Err(self.fail(format!("{name}: matrix {k} is not finite")));
                    }
                    matrices.into_iter().take(joints.len()).collect()
                }
                None => vec![Mat4::IDENTITY; joints.len()],
            };
            let skeleton = skin.skeleton.map(|s| s.value());
            if let Some(k) = skeleton.filter(|&k| k >= self.root.nodes.len()) {
                return Err(self.fail(format!("{what}: skeleton node {k} does not exist")));
            }
            out.push(Skin {
                joints,
                inverse_bind,
                #[cfg(test)]
                skeleton,
            });
        }
        Ok(out)
    }

    /// Joint indices of every mesh drawn with a skin must stay inside that skin.
    pub(super) fn check_skinned_meshes(&mut self, nodes: &[Node], skins: &[Skin], meshes: &mut [Mesh]) -> Result<()> {
        for (i, node) in nodes.iter().enumerate() {
            let Some(s) = node.skin else { continue };
            let skin = skins.get(s).ok_or_else(|| self.fail(format!("node {i}: skin {s} does not exist")))?;
            let Some(m) = node.mesh else {
                self.warnings.push(format!("node {i} has skin {s} but no mesh; skin unused"));
                continue;
            };
            let mesh = meshes.get_mut(m).ok_or_else(|| self.fail(format!("node {i}: mesh {m} does not exist")))?;
            let mesh_label = label("mesh", m, mesh.name.as_deref());
            let joint_count = skin.joints.len();
            for (p, prim) in mesh.primitives.iter_mut().enumerate() {
                let (Some(joints), Some(weights)) = (&mut prim.joints, &prim.weights) else {
                    self.warnings.push(format!(
                        "node {i} uses skin {s}, but {mesh_label} primitive {p} has no \
                         JOINTS_0/WEIGHTS_0; drawn rigid"
                    ));
                    continue;
                };
                let mut zeroed = 0usize;
                for (v, (j, w)) in joints.iter_mut().zip(weights).enumerate() {
                    for (slot, (joint, weight)) in j.iter_mut().zip(w).enumerate() {
                        if (*joint as usize) < joint_count {
                            continue;
                        }
                        if *weight > 0.0 {
                            return Err(Error::Asset {
                                path: self.path.clone(),
                                problem: format!(
                                    "{mesh_label} primitive {p} JOINTS_0: vertex {v} slot \
                                     {slot} uses joint {joint} with weight {weight}, but skin \
                                     {s} (used by node {i}) has {joint_count} joints"
                                ),
                            });
                        }
                        *joint = 0;
                        zeroed += 1;
                    }
                }
                if zeroed > 0 {
                    self.warnings.push(format!(
                        "{mesh_label} primitive {p}: {zeroed} zero-weight joint slots pointed \
                         outside skin {s}; set to joint 0"
                    ));
                }
            }
        }
        Ok(())
    }
}
