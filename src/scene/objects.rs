//! What a frame draws: meshes, the objects placed from them, lights and a camera.

use std::borrow::Cow;
use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec3A, Vec4};

use super::camera::{Camera, Light};
use super::lights::SceneLight;
use super::model::{Material, TextureRgba8};
use super::rig::ObjectRig;
use super::skinning::{blend_joints, skin_normal};
use crate::mesh::MeshData;

/// `Material::default()`, for a reference that outlives any scene.
static DEFAULT_MATERIAL: Material = Material::GLTF_DEFAULT;

#[derive(Debug, Clone)]
pub struct SceneMesh {
    pub name: String,
    pub data: MeshData,
    /// The file's second UV set (glTF TEXCOORD_1), when it has one: a candidate lightmap /
    /// shadow-texture atlas, checked before use.
    pub uv1: Option<Vec<Vec2>>,
    /// COLOR_0, linear RGBA, one per vertex (drawn white when absent).
    pub colors: Option<Vec<Vec4>>,
}

#[derive(Debug, Clone)]
pub struct SceneObject {
    pub name: String,
    pub mesh: usize,
    pub transform: Mat4,
    /// Index into `Scene::materials`.
    pub material: usize,
    /// The scene wants it to cast shadows (a ground plane does not). Each technique decides
    /// how: shadow volumes cast an open or non-manifold mesh two-sided.
    pub casts_shadow: bool,
    /// The skin of a skinned object, for techniques that skin on the GPU. `mesh` holds the same
    /// vertices already posed on the CPU (what the lit pass and shadow volumes draw).
    pub skin: Option<Box<SceneSkin>>,
    /// The animated model and node the object was placed from, for [`Scene::pose_at`].
    pub(crate) rig: Option<ObjectRig>,
    /// Objects placed from the primitives of one glTF mesh on one node share this number
    /// (unique within the scene, see [`Scene::new_mesh_instance`]); `None` for an object that
    /// stands alone. A primitive per material splits a mesh, and ink lines need the whole
    /// mesh to tell a material border from an open edge.
    pub mesh_instance: Option<u32>,
}

impl SceneObject {
    /// A rigid object under a mirroring transform (negative determinant). glTF winds its mesh
    /// clockwise; the loader turns its triangles to face out in the world (`scene::place`), so
    /// in its own space the mesh is wound inside out. A skinned object is placed by its joints,
    /// not its transform, and is never taken as mirrored.
    pub fn mirrored(&self) -> bool {
        Self::mirrors(&self.transform, self.skin.is_some())
    }

    /// [`SceneObject::mirrored`] for an object about to be placed with `transform`.
    pub fn mirrors(transform: &Mat4, skinned: bool) -> bool {
        !skinned && transform.determinant() < 0.0
    }
}

/// A skinned object's bind-pose vertices, four influences each, and this frame's joint palette.
#[derive(Debug, Clone)]
pub struct SceneSkin {
    /// Bind-pose positions and normals, one per vertex of the object's mesh (same indices).
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// Indices into `joint_matrices`.
    pub joints: Vec<[u16; 4]>,
    /// Summing to 1 (the loader renormalises).
    pub weights: Vec<[f32; 4]>,
    /// At most `MAX_JOINTS` matrices, in the object's (mesh node's) space: what the CPU skinning
    /// applied to produce the mesh.
    pub joint_matrices: Vec<Mat4>,
    /// The palette the object's mesh was skinned with when the scene was built: what its
    /// CPU-side copies hold until `Scene::pose_at` moved `joint_matrices` on (`PoseTracker`).
    pub mesh_pose: Vec<Mat4>,
}

impl SceneSkin {
    /// Vertex `v`'s skinning matrix in this frame's palette; `None` for a vertex without
    /// influences or with a joint outside the palette (the loader rules both out).
    fn skin_matrix(&self, v: usize) -> Option<Mat4> {
        blend_joints(self.joints.get(v)?, self.weights.get(v)?, &self.joint_matrices).ok()
    }

    /// The vertices posed by this frame's palette (in the object's space), as the GPU skins
    /// them: what follows the current pose, where the object's mesh keeps the pose the scene
    /// was built in. The arithmetic of `skinning::skin_positions_normals`, so at the build
    /// pose the two agree bit for bit.
    pub fn posed_positions(&self) -> Vec<Vec3> {
        self.positions
            .iter()
            .enumerate()
            .map(|(v, &p)| self.skin_matrix(v).map_or(p, |m| m.transform_point3(p)))
            .collect()
    }

    /// [`SceneSkin::posed_positions`] with normals.
    pub fn posed_positions_normals(&self) -> (Vec<Vec3>, Vec<Vec3>) {
        let mut positions = Vec::with_capacity(self.positions.len());
        let mut normals = Vec::with_capacity(self.normals.len());
        for (v, &p) in self.positions.iter().enumerate() {
            let m = self.skin_matrix(v);
            positions.push(m.map_or(p, |m| m.transform_point3(p)));
            if let Some(&n) = self.normals.get(v) {
                normals.push(m.map_or(n, |m| skin_normal(m, n)));
            }
        }
        (positions, normals)
    }
}

#[derive(Debug, Clone)]
pub struct Scene {
    pub name: String,
    pub meshes: Vec<SceneMesh>,
    pub objects: Vec<SceneObject>,
    /// What the objects are made of: the glTF material model, its texture references indexing
    /// `textures`.
    pub materials: Vec<Material>,
    /// Colour textures (base colour, emissive), shared by the materials that name them.
    pub textures: Vec<Arc<TextureRgba8>>,
    /// Every light, in the order passes draw them; the first that casts shadows is the primary
    /// light ([`Scene::light`]) of the techniques that shadow one light.
    pub lights: Vec<SceneLight>,
    pub ambient: f32,
    pub camera: Camera,
    /// Clear colour (linear RGB); its alpha is set by the technique.
    pub background: Vec3,
}

impl Scene {
    /// A scene with no meshes, objects or materials yet: the common ambient term (0.25) and
    /// sky colour, `camera` and `light`. Built-in scenes, glTF scenes and tests start here.
    pub fn empty(name: &str, camera: Camera, light: Light) -> Scene {
        Scene {
            name: name.to_owned(),
            meshes: Vec::new(),
            objects: Vec::new(),
            materials: Vec::new(),
            textures: Vec::new(),
            lights: vec![SceneLight::from_geometry(light)],
            ambient: 0.25,
            camera,
            background: Vec3::new(0.55, 0.65, 0.78),
        }
    }

    /// The primary light's geometry: the first light that casts shadows, else the first light,
    /// else one straight down.
    pub fn light(&self) -> Light {
        self.primary_light().map_or(Light::Directional { direction: glam::Vec3::NEG_Y }, |l| l.geometry())
    }

    /// The primary light: the first that casts shadows, else the first.
    pub fn primary_light(&self) -> Option<&SceneLight> {
        self.lights.iter().find(|l| l.casts_shadow).or(self.lights.first())
    }

    /// Index of the primary light in `lights`.
    pub fn primary_light_index(&self) -> Option<usize> {
        self.lights.iter().position(|l| l.casts_shadow).or((!self.lights.is_empty()).then_some(0))
    }

    /// Moves the primary light to `light` (a scene without lights gets one).
    pub fn set_light(&mut self, light: Light) {
        match self.primary_light_index() {
            Some(index) => self.lights[index].set_geometry(light),
            None => self.lights.push(SceneLight::from_geometry(light)),
        }
    }

    pub fn add_mesh(&mut self, name: &str, data: MeshData) -> usize {
        self.add_mesh_with_uv1(name, data, None)
    }

    pub fn add_mesh_with_uv1(&mut self, name: &str, data: MeshData, uv1: Option<Vec<Vec2>>) -> usize {
        self.meshes.push(SceneMesh { name: name.to_owned(), data, uv1, colors: None });
        self.meshes.len() - 1
    }

    /// An object of one plain colour (an opaque, untextured material, shared with the objects
    /// of the same colour).
    pub fn add_object(&mut self, name: &str, mesh: usize, transform: Mat4, colour: Vec3, casts_shadow: bool) {
        let plain = Material { base_color: colour.extend(1.0), ..Material::default() };
        let material = match self.materials.iter().position(|m| *m == plain) {
            Some(index) => index,
            None => self.add_material(plain),
        };
        self.add_object_with_material(name, mesh, transform, material, casts_shadow);
    }

    /// An object made of `material` (an index into `materials`).
    pub fn add_object_with_material(
        &mut self,
        name: &str,
        mesh: usize,
        transform: Mat4,
        material: usize,
        casts_shadow: bool,
    ) {
        self.objects.push(SceneObject {
            name: name.to_owned(),
            mesh,
            transform,
            material,
            casts_shadow,
            skin: None,
            rig: None,
            mesh_instance: None,
        });
    }

    /// A mesh-instance number no object of the scene has yet.
    pub fn new_mesh_instance(&self) -> u32 {
        self.objects.iter().filter_map(|o| o.mesh_instance).max().map_or(0, |last| last + 1)
    }

    /// The objects grouped by mesh instance, in the order of their first object: an object
    /// without one is a group of its own.
    pub fn mesh_instances(&self) -> Vec<Vec<usize>> {
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut group_of = std::collections::HashMap::<u32, usize>::new();
        for (index, object) in self.objects.iter().enumerate() {
            match object.mesh_instance.and_then(|instance| group_of.get(&instance)) {
                Some(&group) => groups[group].push(index),
                None => {
                    if let Some(instance) = object.mesh_instance {
                        group_of.insert(instance, groups.len());
                    }
                    groups.push(vec![index]);
                }
            }
        }
        groups
    }

    pub fn add_material(&mut self, material: Material) -> usize {
        self.materials.push(material);
        self.materials.len() - 1
    }

    pub fn add_texture(&mut self, texture: TextureRgba8) -> usize {
        self.textures.push(Arc::new(texture));
        self.textures.len() - 1
    }

    /// The material of `object` (the glTF default for an index out of range, which the scene
    /// builders never make).
    pub fn material_of(&self, object: &SceneObject) -> &Material {
        self.materials.get(object.material).unwrap_or(&DEFAULT_MATERIAL)
    }

    /// The base colour factor of `object`'s material, linear RGB: its colour where one flat
    /// colour is drawn (counting passes, ink).
    pub fn base_colour(&self, object: &SceneObject) -> Vec3 {
        self.materials.get(object.material).map_or(Vec3::ONE, |m| m.base_color.truncate())
    }

    pub fn object(&self, name: &str) -> Option<&SceneObject> {
        self.objects.iter().find(|o| o.name == name)
    }

    /// Object `index`'s vertices in its own space, in the current pose: a skinned object's
    /// skinned by its current palette, any other's its mesh's (borrowed, not copied).
    pub fn posed_positions(&self, index: usize) -> Cow<'_, [Vec3]> {
        let Some(object) = self.objects.get(index) else { return Cow::Borrowed(&[]) };
        match &object.skin {
            Some(skin) => Cow::Owned(skin.posed_positions()),
            None => self.meshes.get(object.mesh).map_or(Cow::Borrowed(&[][..]), |m| Cow::Borrowed(&m.data.positions)),
        }
    }

    /// Object `index`'s vertices in world space, in the current pose.
    pub fn posed_world_positions(&self, index: usize) -> Vec<Vec3> {
        let Some(object) = self.objects.get(index) else { return Vec::new() };
        self.posed_positions(index).iter().map(|p| object.transform.transform_point3(*p)).collect()
    }

    /// World-space bounds of object `index` in its current pose; `None` without vertices.
    /// Every frame for every object (shadow volumes' clipping): a tight SIMD loop, the same
    /// arithmetic as `transform_point3`.
    pub fn posed_bounds(&self, index: usize) -> Option<(Vec3, Vec3)> {
        let object = self.objects.get(index)?;
        let positions = self.posed_positions(index);
        let mut world = positions.iter().map(|&p| object.transform.transform_point3a(Vec3A::from(p)));
        let first = world.next()?;
        let (lo, hi) = world.fold((first, first), |(lo, hi), w| (lo.min(w), hi.max(w)));
        Some((lo.into(), hi.into()))
    }

    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| self.meshes[o.mesh].data.indices.len() / 3).sum()
    }
}

/// Lowest and highest corner of `points`; `None` for no points.
pub fn bounds_of(points: impl IntoIterator<Item = Vec3>) -> Option<(Vec3, Vec3)> {
    points.into_iter().fold(None, |b, w| Some(b.map_or((w, w), |(lo, hi)| (lo.min(w), hi.max(w)))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn objects_group_by_mesh_instance_and_stand_alone_without_one() {
        let camera = Camera::look_at(Vec3::Z, Vec3::ZERO);
        let mut scene = Scene::empty("groups", camera, Light::Directional { direction: Vec3::NEG_Y });
        let mesh = scene.add_mesh("m", MeshData::default());
        let add = |scene: &mut Scene, instance: Option<u32>| {
            scene.add_object("o", mesh, Mat4::IDENTITY, Vec3::ONE, true);
            if let Some(object) = scene.objects.last_mut() {
                object.mesh_instance = instance;
            }
        };
        assert_eq!(scene.new_mesh_instance(), 0);
        add(&mut scene, None);
        add(&mut scene, Some(0));
        add(&mut scene, Some(1));
        add(&mut scene, Some(0));
        add(&mut scene, None);
        assert_eq!(scene.new_mesh_instance(), 2);
        assert_eq!(scene.mesh_instances(), vec![vec![0], vec![1, 3], vec![2], vec![4]]);
    }
}
