//! A loaded scene as plain data, independent of the gltf crate: what the renderer, the mesh
//! tools and the CPU skinning read. Indices between the lists (`Node::mesh`, `Skin::joints`,
//! `Primitive::material`, ...) are checked at load, so a consumer may index with them directly.

use glam::{Mat3, Mat4, Quat, Vec2, Vec3, Vec4};

mod animation_data;

pub use animation_data::{Animation, Channel, ChannelValues, Interpolation, Property};

/// Joint matrices live in one uniform buffer as large as the mobile profile guarantees
/// (maxUniformBufferRange 16 KiB): 256 matrices of 64 bytes, room for the 65-bone rigs common
/// in exported characters. A skin with more joints is rejected at load rather than split.
pub const MAX_JOINTS: usize = crate::gpu::mobile_profile::MAX_UNIFORM_BUFFER_RANGE as usize / 64;

#[derive(Clone, Debug, Default)]
pub struct Model {
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    /// Decoded colour textures (base colour, emissive), in first-use order (not the glTF
    /// texture order).
    pub textures: Vec<TextureRgba8>,
    pub nodes: Vec<Node>,
    /// The nodes of the scene to show: the glTF `scene` (or the first scene), or every node
    /// without a parent when the file has no scenes.
    pub roots: Vec<usize>,
    pub skins: Vec<Skin>,
    pub animations: Vec<Animation>,
    /// The file's cameras, checked as it loads; only the loader's tests read them back.
    #[cfg(test)]
    pub cameras: Vec<Camera>,
    /// KHR_lights_punctual lights, referenced by `Node::light`.
    pub lights: Vec<Light>,
    /// Things that were skipped or repaired while loading (point/line primitives, morph
    /// targets, undecodable textures, renormalised weights). Never errors: those fail the load.
    pub warnings: Vec<String>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub translation: Vec3,
    pub rotation: Quat,
    pub scale: Vec3,
}

impl Transform {
    pub const IDENTITY: Transform = Transform { translation: Vec3::ZERO, rotation: Quat::IDENTITY, scale: Vec3::ONE };

    pub fn to_mat4(self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }

    /// Decomposes an affine matrix. Shear and non-affine parts are lost; the loader warns when
    /// that changes the matrix.
    pub fn from_mat4(m: Mat4) -> Transform {
        let (scale, rotation, translation) = m.to_scale_rotation_translation();
        Transform { translation, rotation: rotation.normalize(), scale }
    }
}

impl Default for Transform {
    fn default() -> Self {
        Transform::IDENTITY
    }
}

#[derive(Clone, Debug, Default)]
pub struct Node {
    pub name: Option<String>,
    pub parent: Option<usize>,
    pub children: Vec<usize>,
    /// Rest pose (the file's TRS or decomposed matrix); animation overrides it per channel.
    pub local: Transform,
    pub mesh: Option<usize>,
    pub skin: Option<usize>,
    /// Only the loader's tests read it back (the frame's camera is the scene's own).
    #[cfg(test)]
    pub camera: Option<usize>,
    pub light: Option<usize>,
}

#[derive(Clone, Debug, Default)]
pub struct Mesh {
    pub name: Option<String>,
    pub primitives: Vec<Primitive>,
}

/// One triangle list. Every per-vertex array has `positions.len()` entries.
#[derive(Clone, Debug, Default)]
pub struct Primitive {
    pub positions: Vec<Vec3>,
    /// Unit normals: the file's, or computed (see `normals_generated`).
    pub normals: Vec<Vec3>,
    /// True when the file had no NORMAL: smooth normals from positions welded by value,
    /// area-weighted. Only the loader's tests read it back.
    #[cfg(test)]
    pub normals_generated: bool,
    pub uv0: Option<Vec<Vec2>>,
    pub uv1: Option<Vec<Vec2>>,
    /// COLOR_0 as linear RGBA (RGB inputs get alpha 1).
    pub colors: Option<Vec<Vec4>>,
    /// JOINTS_0: indices into the skin's `joints` (not node indices). Checked against every
    /// skin the mesh is used with.
    pub joints: Option<Vec<[u16; 4]>>,
    /// WEIGHTS_0, normalised to sum 1. Present exactly when `joints` is.
    pub weights: Option<Vec<[f32; 4]>>,
    /// Triangle list; strips and fans are converted, non-indexed primitives get 0..n.
    pub indices: Vec<u32>,
    /// Bytes per index in the file (1, 2 or 4); `None` when the indices were generated. Only
    /// the loader's tests read it back.
    #[cfg(test)]
    pub source_index_width: Option<u8>,
    pub material: Option<usize>,
}

impl Primitive {
    #[cfg(test)]
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    #[cfg(test)]
    pub fn is_skinned(&self) -> bool {
        self.joints.is_some() && self.weights.is_some()
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    Opaque,
    Mask { cutoff: f32 },
    Blend,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into `Model::textures`.
    pub texture: usize,
    /// Which UV set: 0 = `uv0`, 1 = `uv1` (KHR_texture_transform's `texCoord` override already
    /// applied).
    pub tex_coord: u32,
    /// KHR_texture_transform, applied to the UV before sampling.
    pub transform: Option<TextureTransform>,
}

/// KHR_texture_transform: `uv' = T(offset) * R(rotation) * S(scale) * uv`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureTransform {
    pub offset: Vec2,
    /// Radians, counter-clockwise in UV space.
    pub rotation: f32,
    pub scale: Vec2,
}

impl TextureTransform {
    /// The 3x3 matrix of the extension's text: translation * rotation * scale.
    pub fn matrix(&self) -> Mat3 {
        let translation = Mat3::from_cols(Vec3::X, Vec3::Y, self.offset.extend(1.0));
        let (s, c) = self.rotation.sin_cos();
        let rotation = Mat3::from_cols(Vec3::new(c, -s, 0.0), Vec3::new(s, c, 0.0), Vec3::Z);
        let scale = Mat3::from_diagonal(self.scale.extend(1.0));
        translation * rotation * scale
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: Option<String>,
    /// Linear RGBA factor, multiplied with the texture.
    pub base_color: Vec4,
    pub base_color_texture: Option<TextureRef>,
    pub metallic: f32,
    pub roughness: f32,
    /// Linear RGB factor, multiplied with `emissive_texture`.
    pub emissive: Vec3,
    pub emissive_texture: Option<TextureRef>,
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
    /// KHR_materials_unlit: the base colour is the shaded colour.
    pub unlit: bool,
}

impl Material {
    /// The glTF default material (used for primitives without one), as a constant that a
    /// `static` can hold.
    pub const GLTF_DEFAULT: Material = Material {
        name: None,
        base_color: Vec4::ONE,
        base_color_texture: None,
        metallic: 1.0,
        roughness: 1.0,
        emissive: Vec3::ZERO,
        emissive_texture: None,
        alpha_mode: AlphaMode::Opaque,
        double_sided: false,
        unlit: false,
    };
}

impl Default for Material {
    fn default() -> Self {
        Material::GLTF_DEFAULT
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wrap {
    Repeat,
    MirroredRepeat,
    ClampToEdge,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    Nearest,
    Linear,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampler {
    pub wrap_s: Wrap,
    pub wrap_t: Wrap,
    pub mag_filter: Filter,
    pub min_filter: Filter,
    /// `None` when the file asks for no mipmapping (min filter NEAREST or LINEAR).
    pub mipmap_filter: Option<Filter>,
}

impl Default for Sampler {
    /// What glTF leaves to the implementation: repeat, trilinear.
    fn default() -> Self {
        Sampler {
            wrap_s: Wrap::Repeat,
            wrap_t: Wrap::Repeat,
            mag_filter: Filter::Linear,
            min_filter: Filter::Linear,
            mipmap_filter: Some(Filter::Linear),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct TextureRgba8 {
    pub name: Option<String>,
    pub width: u32,
    pub height: u32,
    /// `width * height * 4` bytes, rows top to bottom.
    pub pixels: Vec<u8>,
    /// Base colour is sRGB-encoded: upload as an `_SRGB` format.
    pub srgb: bool,
    pub sampler: Sampler,
}

#[derive(Clone, Debug, Default)]
pub struct Skin {
    /// Node indices, at most `MAX_JOINTS`.
    pub joints: Vec<usize>,
    /// One per joint (identity when the file has none).
    pub inverse_bind: Vec<Mat4>,
    /// The file's skeleton root, checked as it loads; only the loader's tests read it back.
    #[cfg(test)]
    pub skeleton: Option<usize>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    Perspective {
        yfov: f32,
        aspect_ratio: Option<f32>,
        znear: f32,
        /// `None`: infinite far plane.
        zfar: Option<f32>,
    },
    Orthographic {
        xmag: f32,
        ymag: f32,
        znear: f32,
        zfar: f32,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    pub name: Option<String>,
    pub projection: Projection,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightKind {
    /// Shines along the node's local -Z.
    Directional,
    Point,
    /// Along local -Z; angles in radians from the axis.
    Spot {
        inner_cone_angle: f32,
        outer_cone_angle: f32,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    pub name: Option<String>,
    pub kind: LightKind,
    /// Linear RGB.
    pub color: Vec3,
    /// Candela for point/spot, lux for directional.
    pub intensity: f32,
    /// `None`: infinite.
    pub range: Option<f32>,
}
