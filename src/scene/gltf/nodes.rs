//! The node hierarchy: each node's rest transform (TRS or a decomposed matrix), the parent and
//! child links (checked to form a forest), and the roots of the scene to show.

use glam::{Mat4, Quat, Vec3};
use gltf::json;

use super::loader::{label, Loader};
use crate::error::Result;
use crate::scene::model::{Node, Transform};

impl Loader<'_> {
    pub(super) fn nodes(&mut self) -> Result<Vec<Node>> {
        let count = self.root.nodes.len();
        let mut nodes = Vec::with_capacity(count);
        for (i, n) in self.root.nodes.iter().enumerate() {
            let what = label("node", i, n.name.as_deref());
            let local = self.node_transform(&what, n)?;
            let light = n.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()).map(|l| l.light.value());
            let light_count = self.light_count();
            if let Some(l) = light.filter(|&l| l >= light_count) {
                return Err(self.fail(format!("{what}: light {l} does not exist")));
            }
            let light = match light {
                Some(l) if !self.light_type_is_known(l) => {
                    self.warnings.push(format!("{what}: light {l} has a type this loader does not know; ignored"));
                    None
                }
                other => other,
            };
            nodes.push(Node {
                name: n.name.clone(),
                parent: None,
                children: Vec::new(),
                local,
                mesh: n.mesh.map(|m| m.value()),
                skin: n.skin.map(|s| s.value()),
                #[cfg(test)]
                camera: n.camera.map(|c| c.value()),
                light,
            });
        }
        // Children and parents; the hierarchy must be a forest.
        for i in 0..count {
            let children: Vec<usize> = self
                .root
                .nodes
                .get(i)
                .and_then(|n| n.children.as_ref())
                .map(|c| c.iter().map(|c| c.value()).collect())
                .unwrap_or_default();
            for &c in &children {
                if c == i {
                    return Err(self.fail(format!("node {i} lists itself as a child")));
                }
                let child = nodes.get_mut(c).ok_or_else(|| self.fail(format!("node {i}: child {c} does not exist")))?;
                if let Some(p) = child.parent {
                    return Err(self.fail(format!("node {c} is a child of both node {p} and node {i}")));
                }
                child.parent = Some(i);
            }
            if let Some(node) = nodes.get_mut(i) {
                node.children = children;
            }
        }
        for start in 0..count {
            let mut at = start;
            for _ in 0..=count {
                match nodes.get(at).and_then(|n| n.parent) {
                    Some(p) if p == start => {
                        return Err(self.fail(format!("the node hierarchy has a cycle through node {start}")))
                    }
                    Some(p) => at = p,
                    None => break,
                }
            }
        }
        Ok(nodes)
    }

    fn node_transform(&mut self, what: &str, n: &json::Node) -> Result<Transform> {
        if let Some(m) = n.matrix {
            if m.iter().any(|x| !x.is_finite()) {
                return Err(self.fail(format!("{what}: matrix has a non-finite element")));
            }
            let matrix = Mat4::from_cols_array(&m);
            let det = matrix.determinant();
            let t = if det.abs() > 1e-30 {
                Transform::from_mat4(matrix)
            } else {
                // Singular (a zero scale): keep the axis lengths, drop the rotation.
                Transform {
                    translation: matrix.w_axis.truncate(),
                    rotation: Quat::IDENTITY,
                    scale: Vec3::new(
                        matrix.x_axis.truncate().length(),
                        matrix.y_axis.truncate().length(),
                        matrix.z_axis.truncate().length(),
                    ),
                }
            };
            let error = (t.to_mat4() - matrix).abs().to_cols_array();
            let scale = m.iter().fold(1.0f32, |a, x| a.max(x.abs()));
            if !t.to_mat4().is_finite() || error.iter().any(|e| *e > 1e-4 * scale) {
                self.warnings.push(format!(
                    "{what}: matrix has shear or a projective part; its translation / rotation \
                     / scale approximation is used"
                ));
            }
            return Ok(t);
        }
        let translation = Vec3::from_array(n.translation.unwrap_or([0.0; 3]));
        let scale = Vec3::from_array(n.scale.unwrap_or([1.0; 3]));
        let r = n.rotation.as_ref().map_or([0.0, 0.0, 0.0, 1.0], |r| r.0);
        let rotation = Quat::from_array(r);
        if !translation.is_finite() || !scale.is_finite() || !rotation.is_finite() {
            return Err(self.fail(format!("{what}: non-finite translation, rotation or scale")));
        }
        let len = rotation.length();
        if len < 1e-6 {
            return Err(self.fail(format!("{what}: rotation is a zero quaternion")));
        }
        Ok(Transform { translation, rotation: rotation / len, scale })
    }

    fn light_count(&self) -> usize {
        self.root.extensions.as_ref().and_then(|e| e.khr_lights_punctual.as_ref()).map_or(0, |l| l.lights.len())
    }

    /// A file of meshes and no nodes (valid glTF: a mesh library) would show nothing; each mesh
    /// gets a node of its own at the origin instead, and all of them are roots.
    pub(super) fn nodes_for_unplaced_meshes(&mut self, mesh_count: usize) -> (Vec<Node>, Vec<usize>) {
        self.warnings.push(format!("the file has no nodes; each of its {mesh_count} mesh(es) is shown at the origin"));
        let nodes = (0..mesh_count).map(|m| Node { mesh: Some(m), ..Node::default() }).collect();
        (nodes, (0..mesh_count).collect())
    }

    pub(super) fn roots(&mut self, nodes: &[Node]) -> Vec<usize> {
        let scene = self.root.scene.map(|s| s.value()).or(if self.root.scenes.is_empty() { None } else { Some(0) });
        let Some(scene) = scene.and_then(|s| self.root.scenes.get(s)) else {
            return (0..nodes.len()).filter(|&i| nodes.get(i).is_some_and(|n| n.parent.is_none())).collect();
        };
        let mut roots = Vec::new();
        for index in scene.nodes.iter().map(|n| n.value()) {
            match nodes.get(index).map(|n| n.parent) {
                Some(None) => roots.push(index),
                Some(Some(p)) => {
                    self.warnings.push(format!("scene lists node {index}, which is a child of node {p}; skipped"))
                }
                None => self.warnings.push(format!("scene lists node {index}, which does not exist")),
            }
        }
        roots
    }
}
