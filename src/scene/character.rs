//! A skinned character built in code: a torso with a head, two arms and two legs, each a box
//! bound to a joint of a six-joint skeleton, walking in place. It is a `Model` like a loaded
//! glTF file, so it goes through the same CPU skinning (the oracle) and keeps its skin for
//! GPU skinning. The arms swing beside the torso, so under a light from the side their
//! projected shadows overlap the torso's: the case where double darkening shows.
//!
//! Every box is closed and no two boxes share a vertex position, so the welded mesh is a closed
//! manifold (several components), and it casts shadow volumes like any closed mesh.

use std::f32::consts::TAU;
use std::sync::Arc;

use glam::{Mat4, Quat, Vec3};

use super::model::{Material, Mesh, Model, Node, Primitive, Skin, Transform};
use super::objects::Scene;
use super::place::add_model;
use super::rig::{PoseSource, Rig, RigPose};
use super::skinning::world_matrices;
use crate::error::{Error, Result};

/// Node indices of the skeleton (the skin's joints are nodes 1..=6, palette entries 0..=5).
const ROOT: usize = 0;
const HIPS: usize = 1;
const SPINE: usize = 2;
const LEFT_SHOULDER: usize = 3;
const RIGHT_SHOULDER: usize = 4;
const LEFT_HIP: usize = 5;
const RIGHT_HIP: usize = 6;
const BODY: usize = 7;

/// Palette index of a joint node.
const fn joint(node: usize) -> u16 {
    (node - HIPS) as u16
}

/// One walk cycle, in seconds.
pub const WALK_PERIOD: f32 = 1.0;

/// Height of the character (feet at y = 0, top of the head).
pub const HEIGHT: f32 = 1.88;

/// Bind-pose local translations of the joints (the rest pose).
fn rest_translation(node: usize) -> Vec3 {
    match node {
        HIPS => Vec3::new(0.0, 0.95, 0.0),
        SPINE => Vec3::new(0.0, 0.1, 0.0),
        LEFT_SHOULDER => Vec3::new(-0.32, 0.5, 0.0),
        RIGHT_SHOULDER => Vec3::new(0.32, 0.5, 0.0),
        LEFT_HIP => Vec3::new(-0.12, -0.03, 0.0),
        RIGHT_HIP => Vec3::new(0.12, -0.03, 0.0),
        _ => Vec3::ZERO,
    }
}

/// How a box's vertices are weighted: rigidly to one joint, or blended at one end.
struct Part {
    min: Vec3,
    max: Vec3,
    joint: usize,
    /// Vertices with y == max.y (top) or y == min.y (bottom) get `[joint, other]` with weights
    /// `[1 - w, w]`: four-influence skinning exercised with two non-zero weights.
    blend: Option<(bool, usize, f32)>,
}

fn parts() -> [Part; 6] {
    let v = Vec3::new;
    [
        // Torso: its bottom ring blends hips and spine, so it bends at the waist.
        Part { min: v(-0.22, 0.9, -0.13), max: v(0.22, 1.6, 0.13), joint: SPINE, blend: Some((false, HIPS, 0.5)) },
        Part { min: v(-0.11, 1.64, -0.11), max: v(0.11, HEIGHT, 0.11), joint: SPINE, blend: None },
        Part { min: v(-0.39, 0.85, -0.07), max: v(-0.25, 1.58, 0.07), joint: LEFT_SHOULDER, blend: None },
        Part { min: v(0.25, 0.85, -0.07), max: v(0.39, 1.58, 0.07), joint: RIGHT_SHOULDER, blend: None },
        // Legs: the top (inside the torso) follows the hips by 30 %.
        Part { min: v(-0.2, 0.0, -0.08), max: v(-0.04, 0.93, 0.08), joint: LEFT_HIP, blend: Some((true, HIPS, 0.3)) },
        Part { min: v(0.04, 0.0, -0.08), max: v(0.2, 0.93, 0.08), joint: RIGHT_HIP, blend: Some((true, HIPS, 0.3)) },
    ]
}

/// A box as 24 vertices (flat normals) and 12 counter-clockwise triangles seen from outside.
fn push_box(prim: &mut Primitive, part: &Part) {
    let centre = (part.min + part.max) * 0.5;
    let half = (part.max - part.min) * 0.5;
    let axes = [Vec3::X, Vec3::Y, Vec3::Z];
    for a in 0..3 {
        for sign in [1.0f32, -1.0] {
            let n = axes[a] * sign;
            // u x v = n for the positive face; swapped for the negative one.
            let (mut u, mut v) = (axes[(a + 1) % 3], axes[(a + 2) % 3]);
            if sign < 0.0 {
                std::mem::swap(&mut u, &mut v);
            }
            let base = prim.positions.len() as u32;
            for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let p = centre + (n + u * su + v * sv) * half;
                prim.positions.push(p);
                prim.normals.push(n);
                let (joints, weights) = match part.blend {
                    Some((top, other, w)) if (p.y - if top { part.max.y } else { part.min.y }).abs() < 1e-6 => {
                        ([joint(part.joint), joint(other), 0, 0], [1.0 - w, w, 0.0, 0.0])
                    }
                    _ => ([joint(part.joint), 0, 0, 0], [1.0, 0.0, 0.0, 0.0]),
                };
                prim.joints.get_or_insert_with(Vec::new).push(joints);
                prim.weights.get_or_insert_with(Vec::new).push(weights);
            }
            prim.indices.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
}

/// The character as a model: a placement root, the skeleton under it and the skinned body.
pub fn character_model() -> Model {
    let mut primitive = Primitive::default();
    for part in &parts() {
        push_box(&mut primitive, part);
    }
    let node = |name: &str, parent: Option<usize>, children: Vec<usize>, index: usize| Node {
        name: Some(name.to_owned()),
        parent,
        children,
        local: Transform { translation: rest_translation(index), ..Transform::IDENTITY },
        ..Node::default()
    };
    let mut nodes = vec![
        node("character", None, vec![HIPS, BODY], ROOT),
        node("hips", Some(ROOT), vec![SPINE, LEFT_HIP, RIGHT_HIP], HIPS),
        node("spine", Some(HIPS), vec![LEFT_SHOULDER, RIGHT_SHOULDER], SPINE),
        node("left shoulder", Some(SPINE), vec![], LEFT_SHOULDER),
        node("right shoulder", Some(SPINE), vec![], RIGHT_SHOULDER),
        node("left hip", Some(HIPS), vec![], LEFT_HIP),
        node("right hip", Some(HIPS), vec![], RIGHT_HIP),
        node("body", Some(ROOT), vec![], BODY),
    ];
    nodes[BODY].mesh = Some(0);
    nodes[BODY].skin = Some(0);
    let mut model = Model {
        meshes: vec![Mesh { name: Some("character".into()), primitives: vec![primitive] }],
        nodes,
        roots: vec![ROOT],
        ..Model::default()
    };
    // Inverse bind matrices from the rest pose: joint matrices are identity at rest.
    let rest: Vec<Transform> = model.nodes.iter().map(|n| n.local).collect();
    let world = world_matrices(&model, &rest);
    let joints: Vec<usize> = (HIPS..=RIGHT_HIP).collect();
    let inverse_bind = joints.iter().map(|&j| world[j].inverse()).collect();
    model.skins.push(Skin {
        joints,
        inverse_bind,
        #[cfg(test)]
        skeleton: Some(HIPS),
    });
    model
}

/// Local transforms of every node at `time` seconds of the walk, the root placed at `placement`.
pub fn walk_pose(model: &Model, placement: Mat4, time: f32) -> Vec<Transform> {
    let phase = (time / WALK_PERIOD).rem_euclid(1.0) * TAU;
    let swing = phase.sin();
    let mut pose: Vec<Transform> = model.nodes.iter().map(|n| n.local).collect();
    let mut rotate = |node: usize, rotation: Quat| {
        if let Some(t) = pose.get_mut(node) {
            t.rotation = rotation;
        }
    };
    rotate(HIPS, Quat::from_rotation_y(0.08 * swing));
    rotate(SPINE, Quat::from_rotation_y(0.12 * swing) * Quat::from_rotation_x(0.05));
    // Arms swing against the legs on the same side, slightly away from the body.
    rotate(LEFT_SHOULDER, Quat::from_rotation_x(0.7 * swing) * Quat::from_rotation_z(-0.12));
    rotate(RIGHT_SHOULDER, Quat::from_rotation_x(-0.7 * swing) * Quat::from_rotation_z(0.12));
    rotate(LEFT_HIP, Quat::from_rotation_x(-0.5 * swing));
    rotate(RIGHT_HIP, Quat::from_rotation_x(0.5 * swing));
    if let Some(root) = pose.get_mut(ROOT) {
        *root = Transform::from_mat4(placement);
    }
    pose
}

/// The walk as the character's rig plays it, the root held at `placement`.
#[derive(Debug)]
struct Walk {
    placement: Mat4,
}

impl PoseSource for Walk {
    fn local_pose(&self, model: &Model, time: f32) -> Vec<Transform> {
        walk_pose(model, self.placement, time)
    }
}

/// Adds the character, placed by `placement` (a rigid transform) and posed at `time` seconds.
pub fn add_character(scene: &mut Scene, placement: Mat4, time: f32, colour: Vec3) -> Result<()> {
    if !time.is_finite() {
        return Err(Error::InvalidInput(format!("animation time {time} is not a finite number of seconds")));
    }
    let rig = Arc::new(Rig { model: character_model(), pose: RigPose::Procedural(Arc::new(Walk { placement })) });
    let world = world_matrices(&rig.model, &walk_pose(&rig.model, placement, time));
    let first = scene.objects.len();
    add_model(scene, &rig, &world)?;
    let material = scene.add_material(Material { base_color: colour.extend(1.0), ..Material::default() });
    for object in &mut scene.objects[first..] {
        object.name = "character".into();
        object.material = material;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Camera, Light};

    #[test]
    fn the_character_is_skinned_closed_and_moves() {
        let mut scene = crate::scene::Scene::empty(
            "t",
            Camera::look_at(Vec3::Z, Vec3::ZERO),
            Light::Directional { direction: -Vec3::Y },
        );
        add_character(&mut scene, Mat4::IDENTITY, 0.0, Vec3::ONE).unwrap();
        let object = &scene.objects[0];
        let skin = object.skin.as_ref().expect("skinned");
        assert_eq!(skin.joint_matrices.len(), 6);
        let data = &scene.meshes[object.mesh].data;
        let welded = crate::mesh::weld_by_position("character", &data.positions, &data.indices, 1e-5).unwrap();
        let adjacency = crate::mesh::EdgeAdjacency::build("character", &welded.positions, &welded.indices).unwrap();
        assert!(adjacency.require_closed_manifold().is_ok(), "six closed boxes weld to a closed mesh");
        // At t = 0 the swing is zero: the legs' feet rest on the ground.
        let low = scene.meshes[0].data.positions.iter().map(|p| p.y).fold(f32::MAX, f32::min);
        assert!(low.abs() < 0.02, "{low}");

        let mut later = crate::scene::Scene::empty(
            "t",
            Camera::look_at(Vec3::Z, Vec3::ZERO),
            Light::Directional { direction: -Vec3::Y },
        );
        add_character(&mut later, Mat4::IDENTITY, WALK_PERIOD * 0.25, Vec3::ONE).unwrap();
        let moved = scene.meshes[0]
            .data
            .positions
            .iter()
            .zip(&later.meshes[0].data.positions)
            .filter(|(a, b)| (**a - **b).length() > 0.05)
            .count();
        assert!(moved > 24, "a quarter cycle later the limbs have moved ({moved} vertices)");
        assert!(add_character(&mut later, Mat4::IDENTITY, f32::NAN, Vec3::ONE).is_err());
    }
}
