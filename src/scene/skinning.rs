//! Node hierarchy and linear blend skinning on the CPU. Used to extrude shadow volumes from the
//! posed mesh and as the oracle the GPU skinning shader is tested against.
//!
//! glTF skinning (spec section 3.7.3): for joint j of the skin used by mesh node N,
//! `joint_matrix[j] = inverse(world(N)) * world(joint j) * inverse_bind[j]`, and a vertex goes to
//! `sum_k weight_k * joint_matrix[joint_k] * position`. The result is in N's local space, so
//! the renderer still applies world(N) afterwards, exactly as for an unskinned mesh.

use glam::{Mat3, Mat4, Vec3};

use super::model::{Model, Primitive, Transform};
use crate::error::{Error, Result};

/// World matrices of all nodes for the given local transforms (`local[i]` for node `i`; nodes
/// beyond `local.len()` use their rest pose). Parents are visited before children.
pub fn world_matrices(model: &Model, local: &[Transform]) -> Vec<Mat4> {
    let count = model.nodes.len();
    let local_of = |i: usize| {
        local.get(i).or_else(|| model.nodes.get(i).map(|n| &n.local)).map_or(Mat4::IDENTITY, |t| t.to_mat4())
    };
    let mut world = vec![Mat4::IDENTITY; count];
    let mut visited = vec![false; count];
    let mut stack: Vec<(usize, Mat4)> = Vec::new();
    for (root, node) in model.nodes.iter().enumerate() {
        if node.parent.is_some() {
            continue;
        }
        stack.push((root, Mat4::IDENTITY));
        while let Some((i, parent_world)) = stack.pop() {
            // `visited` guards against a hand-built model with a cycle; loaded ones have none.
            let (Some(seen), Some(node)) = (visited.get_mut(i), model.nodes.get(i)) else {
                continue;
            };
            if *seen {
                continue;
            }
            *seen = true;
            let w = parent_world * local_of(i);
            if let Some(slot) = world.get_mut(i) {
                *slot = w;
            }
            stack.extend(node.children.iter().map(|&c| (c, w)));
        }
    }
    world
}

/// The joint palette of skin `skin_index` for a mesh whose node has world matrix
/// `mesh_node_world`: one matrix per joint, in the skin's joint order (what JOINTS_0 indexes).
/// A singular `mesh_node_world` (zero scale: nothing visible) is treated as identity.
pub fn joint_matrices(model: &Model, skin_index: usize, world: &[Mat4], mesh_node_world: Mat4) -> Result<Vec<Mat4>> {
    let skin = model.skins.get(skin_index).ok_or_else(|| {
        Error::InvalidInput(format!("skin {skin_index} does not exist (the model has {})", model.skins.len()))
    })?;
    let inverse_mesh = if mesh_node_world.determinant().abs() > f32::MIN_POSITIVE {
        mesh_node_world.inverse()
    } else {
        Mat4::IDENTITY
    };
    skin.joints
        .iter()
        .enumerate()
        .map(|(j, &node)| {
            let joint_world = world.get(node).ok_or_else(|| {
                Error::InvalidInput(format!(
                    "skin {skin_index} joint {j} is node {node}, but only {} world matrices \
                     were given",
                    world.len()
                ))
            })?;
            let inverse_bind = skin.inverse_bind.get(j).copied().unwrap_or(Mat4::IDENTITY);
            Ok(inverse_mesh * *joint_world * inverse_bind)
        })
        .collect()
}

/// Skins one primitive: `out_positions` / `out_normals` are replaced with the posed vertices
/// (in the mesh node's space). Positions use the weighted sum of joint matrices; normals use
/// the inverse transpose of its upper 3x3 (correct under non-uniform scale), renormalised. An
/// unskinned primitive is copied through. Joint indices beyond `joint_matrices` are an error
/// (the loader guarantees they fit the skin the mesh is used with).
pub fn skin_positions_normals(
    primitive: &Primitive,
    joint_matrices: &[Mat4],
    out_positions: &mut Vec<Vec3>,
    out_normals: &mut Vec<Vec3>,
) -> Result<()> {
    out_positions.clear();
    out_normals.clear();
    let (Some(joints), Some(weights)) = (&primitive.joints, &primitive.weights) else {
        out_positions.extend_from_slice(&primitive.positions);
        out_normals.extend_from_slice(&primitive.normals);
        return Ok(());
    };
    out_positions.reserve(primitive.positions.len());
    out_normals.reserve(primitive.normals.len());
    for (v, &p) in primitive.positions.iter().enumerate() {
        let (Some(j), Some(w)) = (joints.get(v), weights.get(v)) else {
            return Err(Error::InvalidInput(format!("vertex {v} has no joints or weights")));
        };
        let m = blend_joints(j, w, joint_matrices).map_err(|joint| {
            Error::InvalidInput(format!(
                "vertex {v} uses joint {joint}, but only {} joint matrices were given",
                joint_matrices.len()
            ))
        })?;
        out_positions.push(m.transform_point3(p));
        if let Some(&n) = primitive.normals.get(v) {
            out_normals.push(skin_normal(m, n));
        }
    }
    Ok(())
}

/// A vertex's skinning matrix: the weighted sum of its joints' matrices (zero weights
/// skipped). `Err(joint)`: a weighted joint outside `palette`.
pub fn blend_joints(joints: &[u16; 4], weights: &[f32; 4], palette: &[Mat4]) -> std::result::Result<Mat4, u16> {
    let mut m = Mat4::ZERO;
    for (&joint, &weight) in joints.iter().zip(weights) {
        if weight != 0.0 {
            m += *palette.get(joint as usize).ok_or(joint)? * weight;
        }
    }
    Ok(m)
}

/// A normal under skinning matrix `m`: the inverse transpose of its upper 3x3 (right under
/// non-uniform scale), renormalised.
pub fn skin_normal(m: Mat4, n: Vec3) -> Vec3 {
    let m3 = Mat3::from_mat4(m);
    let normal_matrix = if m3.determinant().abs() > f32::MIN_POSITIVE { m3.inverse().transpose() } else { m3 };
    (normal_matrix * n).try_normalize().unwrap_or(n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::model::{Node, Skin};
    use glam::Quat;

    /// root (translate x+1) -> child (rotate 90 deg about z) -> grandchild (translate y+2).
    fn chain() -> Model {
        let t = |translation: Vec3, rotation: Quat| Transform { translation, rotation, scale: Vec3::ONE };
        Model {
            nodes: vec![
                Node { children: vec![1], local: t(Vec3::X, Quat::IDENTITY), ..Node::default() },
                Node {
                    parent: Some(0),
                    children: vec![2],
                    local: t(Vec3::ZERO, Quat::from_rotation_z(std::f32::consts::FRAC_PI_2)),
                    ..Node::default()
                },
                Node { parent: Some(1), local: t(Vec3::new(0.0, 2.0, 0.0), Quat::IDENTITY), ..Node::default() },
            ],
            ..Model::default()
        }
    }

    #[test]
    fn world_matrices_compose_parent_first() {
        let model = chain();
        let world = world_matrices(&model, &crate::scene::animation::rest_pose(&model));
        let origin = |i: usize| world[i].transform_point3(Vec3::ZERO);
        assert!((origin(0) - Vec3::X).length() < 1e-6);
        assert!((origin(1) - Vec3::X).length() < 1e-6);
        // y+2 rotated 90 deg about z is x-2; plus the root's x+1.
        assert!((origin(2) - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-6, "{}", origin(2));
    }

    #[test]
    fn bind_pose_skinning_is_identity_and_weights_blend() {
        let mut model = chain();
        let world = world_matrices(&model, &crate::scene::animation::rest_pose(&model));
        // Inverse binds taken from the rest pose: joint matrices are then identity.
        model.skins.push(Skin {
            joints: vec![1, 2],
            inverse_bind: vec![world[1].inverse(), world[2].inverse()],
            skeleton: None,
        });
        let palette = joint_matrices(&model, 0, &world, Mat4::IDENTITY).unwrap();
        assert!(palette.iter().all(|m| m.abs_diff_eq(Mat4::IDENTITY, 1e-6)));

        // Move joint 2 up by 1 in its parent's frame: half-weighted vertices move half as far.
        let mut pose = crate::scene::animation::rest_pose(&model);
        pose[2].translation.y += 1.0;
        let posed = world_matrices(&model, &pose);
        let palette = joint_matrices(&model, 0, &posed, Mat4::IDENTITY).unwrap();
        let prim = Primitive {
            positions: vec![Vec3::ZERO, Vec3::ZERO],
            normals: vec![Vec3::Z, Vec3::Z],
            joints: Some(vec![[0, 1, 0, 0], [1, 0, 0, 0]]),
            weights: Some(vec![[0.5, 0.5, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]]),
            ..Primitive::default()
        };
        let (mut p, mut n) = (Vec::new(), Vec::new());
        skin_positions_normals(&prim, &palette, &mut p, &mut n).unwrap();
        // The child frame is rotated 90 deg: its +y is world -x.
        assert!((p[0] - Vec3::new(-0.5, 0.0, 0.0)).length() < 1e-6, "{}", p[0]);
        assert!((p[1] - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-6, "{}", p[1]);
        assert!((n[0] - Vec3::Z).length() < 1e-6);

        // A joint index outside the palette is an error, not a panic.
        assert!(skin_positions_normals(&prim, &palette[..1], &mut p, &mut n).is_err());
        assert!(joint_matrices(&model, 1, &posed, Mat4::IDENTITY).is_err());
    }

    #[test]
    fn normals_use_the_inverse_transpose() {
        // Non-uniform scale x2 in x: a normal along (1,1,0) must tilt towards y.
        let prim = Primitive {
            positions: vec![Vec3::ZERO],
            normals: vec![Vec3::new(1.0, 1.0, 0.0).normalize()],
            joints: Some(vec![[0; 4]]),
            weights: Some(vec![[1.0, 0.0, 0.0, 0.0]]),
            ..Primitive::default()
        };
        let palette = [Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0))];
        let (mut p, mut n) = (Vec::new(), Vec::new());
        skin_positions_normals(&prim, &palette, &mut p, &mut n).unwrap();
        let expected = Vec3::new(0.5, 1.0, 0.0).normalize();
        assert!((n[0] - expected).length() < 1e-6, "{}", n[0]);
    }
}
