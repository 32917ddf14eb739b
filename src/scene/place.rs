//! Placing a model in a scene: one object per mesh primitive of the nodes it shows, posed on
//! the CPU, each keeping its skin and its rig so that the scene can be re-posed later. Used by
//! glTF scenes and by the built-in character alike.

use std::sync::Arc;

use glam::{Mat4, Vec3};

use super::model::{Material, Model, TextureRef};
use super::objects::{Scene, SceneObject, SceneSkin};
use super::rig::{ObjectRig, Rig};
use super::skinning::{joint_matrices, skin_positions_normals};
use crate::error::Result;
use crate::mesh::MeshData;

/// Adds every mesh primitive of `rig`'s model to `scene`, posed by the nodes' world matrices
/// `world`: skinned primitives are skinned on the CPU into the object's mesh and keep their
/// skin (bind-pose vertices, joints, weights, this pose's joint palette) for GPU skinning. When
/// the rig moves (an animation, the walk), each object keeps its node so that
/// [`Scene::pose_at`] can re-pose it. Returns the world-space bounds of what was added, `None`
/// when nothing was.
pub fn add_model(scene: &mut Scene, rig: &Arc<Rig>, world: &[Mat4]) -> Result<Option<(Vec3, Vec3)>> {
    let model = &rig.model;
    let animated = rig.moves();
    let (mut low, mut high) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    let shown = nodes_in_scene(model);
    let materials = add_materials(scene, model);
    let mut default_material = None;
    // One mesh-instance number per node that shows a mesh, after those the scene already has.
    let mut next_instance = scene.new_mesh_instance();
    for (node_index, node) in model.nodes.iter().enumerate() {
        if !shown[node_index] {
            continue;
        }
        let Some(mesh) = node.mesh.and_then(|m| model.meshes.get(m)) else { continue };
        let node_world = world.get(node_index).copied().unwrap_or(Mat4::IDENTITY);
        let joints = match node.skin {
            Some(skin) => Some(joint_matrices(model, skin, world, node_world)?),
            None => None,
        };
        let instance = next_instance;
        next_instance += 1;
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let (mut positions, mut normals) = (primitive.positions.clone(), primitive.normals.clone());
            let mut skin = None;
            if let (Some(palette), Some(vertex_joints), Some(weights)) =
                (&joints, &primitive.joints, &primitive.weights)
            {
                skin_positions_normals(primitive, palette, &mut positions, &mut normals)?;
                skin = Some(Box::new(SceneSkin {
                    positions: primitive.positions.clone(),
                    normals: primitive.normals.clone(),
                    joints: vertex_joints.clone(),
                    weights: weights.clone(),
                    joint_matrices: palette.clone(),
                    mesh_pose: palette.clone(),
                }));
            }
            for p in &positions {
                let w = node_world.transform_point3(*p);
                (low, high) = (low.min(w), high.max(w));
            }
            let material = match primitive.material.and_then(|m| materials.get(m)) {
                Some(&index) => index,
                None => *default_material.get_or_insert_with(|| scene.add_material(Material::default())),
            };
            let label = format!(
                "{}#{p}",
                mesh.name.clone().or_else(|| node.name.clone()).unwrap_or_else(|| format!("node {node_index}"))
            );
            let mut indices = primitive.indices.clone();
            // glTF winds a mesh under a mirroring node (negative determinant) clockwise; every
            // pass here takes counter-clockwise fronts, so its triangles are turned: in the
            // world they then face out as the file means. (A skinned mesh's node transform is
            // not its placement; its joints decide, and it is left as it is.)
            if SceneObject::mirrors(&node_world, skin.is_some()) {
                indices.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
            }
            let data = MeshData { positions, normals, uvs: primitive.uv0.clone().unwrap_or_default(), indices };
            // Every mesh of the file casts: each technique decides how (shadow volumes cast an
            // open or non-manifold mesh two-sided) and names in a warning what it cannot use.
            let mesh_index = scene.add_mesh_with_uv1(&label, data, primitive.uv1.clone());
            scene.meshes[mesh_index].colors = primitive.colors.clone();
            scene.add_object_with_material(&label, mesh_index, node_world, material, true);
            if let Some(object) = scene.objects.last_mut() {
                object.rig = animated.then(|| ObjectRig {
                    rig: Arc::clone(rig),
                    node: node_index,
                    skin: node.skin.filter(|_| skin.is_some()),
                });
                object.skin = skin;
                object.mesh_instance = Some(instance);
            }
        }
    }
    Ok((low.x <= high.x).then_some((low, high)))
}

/// Adds `model`'s textures and materials to `scene` (texture references re-pointed at the
/// scene's list); returns the scene index of each model material.
fn add_materials(scene: &mut Scene, model: &Model) -> Vec<usize> {
    let first_texture = scene.textures.len();
    scene.textures.extend(model.textures.iter().cloned().map(Arc::new));
    let moved = |t: Option<TextureRef>| t.map(|t| TextureRef { texture: t.texture + first_texture, ..t });
    model
        .materials
        .iter()
        .map(|m| {
            scene.add_material(Material {
                base_color_texture: moved(m.base_color_texture),
                emissive_texture: moved(m.emissive_texture),
                ..m.clone()
            })
        })
        .collect()
}

/// The nodes of the file's scene (its `scene`, else the first): the roots and their
/// descendants. Nodes of other scenes and orphans are not drawn.
fn nodes_in_scene(model: &Model) -> Vec<bool> {
    let mut shown = vec![false; model.nodes.len()];
    let mut stack: Vec<usize> = model.roots.clone();
    while let Some(index) = stack.pop() {
        let Some(flag) = shown.get_mut(index) else { continue };
        if !*flag {
            *flag = true;
            stack.extend(model.nodes[index].children.iter().copied());
        }
    }
    shown
}
