//! Atlas UVs for shadow textures: each surface point needs a texel of its own. A geometry image
//! has them by construction; other meshes use a UV set of the file when it is checked not to
//! overlap (TEXCOORD_1, then TEXCOORD_0), else a generated atlas (`mesh::atlas_charts`): charts grown over
//! triangles facing nearly the same way, packed with padding between charts.

use glam::{Vec2, Vec3};

use crate::error::Result;
use crate::mesh::atlas_charts::{self, overlap};
use crate::mesh::{geometry_image, MeshData};

/// Where a mesh's atlas UVs came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum AtlasSource {
    /// An n x n geometry image: the grid coordinate.
    GeometryImage { n: u32 },
    /// The file's second UV set, checked not to overlap.
    TexCoord1,
    /// The mesh's first UV set, checked not to overlap.
    TexCoord0,
    /// Charts grown over nearly coplanar triangles, packed with `padding` texels around each.
    Generated { charts: u32, padding: u32 },
    /// No atlas: the projective texture is laid out by the light's view.
    LightView,
}

impl AtlasSource {
    pub fn describe(&self) -> String {
        match self {
            AtlasSource::GeometryImage { n } => format!("geometry image {n}x{n}"),
            AtlasSource::TexCoord1 => "TEXCOORD_1 (non-overlapping)".into(),
            AtlasSource::TexCoord0 => "TEXCOORD_0 (non-overlapping)".into(),
            AtlasSource::Generated { charts, padding } => {
                format!("generated atlas ({charts} charts, {padding} texels padding)")
            }
            AtlasSource::LightView => "the light's view (projective, no atlas)".into(),
        }
    }
}

/// A mesh laid out in its atlas: the vertices to draw (a generated atlas splits them per
/// chart), the shadow texture's size, how far to dilate, and how many mips stay clean.
#[derive(Debug, Clone)]
pub struct MeshAtlas {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub indices: Vec<u32>,
    /// Per atlas vertex, the mesh vertex it copies (a generated atlas has one per corner), so
    /// that a re-posed skin can be laid out again.
    pub source_vertices: Vec<u32>,
    pub source: AtlasSource,
    pub size: u32,
    pub dilate_radius: u32,
    pub mip_levels: u32,
    /// Why the file's TEXCOORD_1 was not used, when it has one.
    pub rejected_uv1: Option<String>,
}

/// Padding around each generated chart, in texels of mip 0.
pub const CHART_PADDING: u32 = 4;

/// The atlas of `mesh` (`name` in errors): `uv1` is the file's TEXCOORD_1 when it has one;
/// `size` the shadow texture size for meshes that are not geometry images.
pub fn mesh_atlas(name: &str, mesh: &MeshData, uv1: Option<&[Vec2]>, size: u32) -> Result<MeshAtlas> {
    if let Some(n) = geometry_image::grid_size(mesh) {
        let size = (n - 1).next_power_of_two();
        return Ok(MeshAtlas {
            positions: mesh.positions.clone(),
            normals: mesh.normals.clone(),
            uvs: mesh.uvs.clone(),
            indices: mesh.indices.clone(),
            source_vertices: (0..mesh.positions.len() as u32).collect(),
            source: AtlasSource::GeometryImage { n },
            size,
            // One chart filling the square: nothing to dilate into but stray uncovered texels.
            dilate_radius: 2,
            mip_levels: crate::gpu::texture::mip_count(size, size),
            rejected_uv1: None,
        });
    }
    let from_file = |uvs: &[Vec2], source| MeshAtlas {
        positions: mesh.positions.clone(),
        normals: mesh.normals.clone(),
        uvs: uvs.to_vec(),
        indices: mesh.indices.clone(),
        source_vertices: (0..mesh.positions.len() as u32).collect(),
        source,
        size,
        dilate_radius: CHART_PADDING,
        mip_levels: clean_mips(CHART_PADDING),
        rejected_uv1: None,
    };
    let rejected_uv1 = match uv1 {
        None => None,
        Some(uv1) if uv1.len() != mesh.positions.len() => {
            Some(format!("{} TEXCOORD_1 values for {} vertices", uv1.len(), mesh.positions.len()))
        }
        Some(uv1) => match overlap(uv1, &mesh.indices, size) {
            None => return Ok(from_file(uv1, AtlasSource::TexCoord1)),
            Some(problem) => Some(problem),
        },
    };
    let mut atlas = if mesh.uvs.len() == mesh.positions.len() && overlap(&mesh.uvs, &mesh.indices, size).is_none() {
        from_file(&mesh.uvs, AtlasSource::TexCoord0)
    } else {
        generated_atlas(name, mesh, size)?
    };
    atlas.rejected_uv1 = rejected_uv1;
    Ok(atlas)
}

/// The projective texture's layout: the mesh as it is (its UVs unused), a `size` texture seen
/// from the light with every mip and nothing to dilate.
pub fn light_view_layout(mesh: &MeshData, size: u32) -> MeshAtlas {
    MeshAtlas {
        positions: mesh.positions.clone(),
        normals: mesh.normals.clone(),
        uvs: vec![Vec2::ZERO; mesh.positions.len()],
        indices: mesh.indices.clone(),
        source_vertices: (0..mesh.positions.len() as u32).collect(),
        source: AtlasSource::LightView,
        size,
        dilate_radius: 0,
        mip_levels: crate::gpu::texture::mip_count(size, size),
        rejected_uv1: None,
    }
}

/// Mips whose texels stay within half the padding: level k averages 2^k texels a side.
fn clean_mips(padding: u32) -> u32 {
    1 + (padding.max(1)).ilog2()
}

/// A generated atlas (see `mesh::atlas_charts`): every corner gets a vertex of its own, since a vertex on
/// a chart border has a UV in each chart.
pub fn generated_atlas(name: &str, mesh: &MeshData, size: u32) -> Result<MeshAtlas> {
    let generated = atlas_charts::generate(name, mesh, size, CHART_PADDING)?;
    let corner = |k: usize| mesh.indices[k] as usize;
    let corners = 0..mesh.indices.len() - mesh.indices.len() % 3;
    Ok(MeshAtlas {
        positions: corners.clone().map(|k| mesh.positions[corner(k)]).collect(),
        normals: corners.clone().map(|k| mesh.normals.get(corner(k)).copied().unwrap_or(Vec3::Y)).collect(),
        uvs: generated.corner_uvs,
        indices: corners.clone().map(|k| k as u32).collect(),
        source_vertices: corners.map(|k| mesh.indices[k]).collect(),
        source: AtlasSource::Generated { charts: generated.charts, padding: generated.padding },
        size,
        dilate_radius: generated.padding,
        mip_levels: clean_mips(generated.padding),
        rejected_uv1: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::shapes;

    #[test]
    fn cube_uvs_overlap_and_are_replaced() {
        let cube = shapes::cube(1.0);
        assert!(overlap(&cube.uvs, &cube.indices, 64).is_some());
        let atlas = mesh_atlas("cube", &cube, Some(&cube.uvs), 64).expect("atlas");
        assert_eq!(atlas.source, AtlasSource::Generated { charts: 6, padding: CHART_PADDING });
        assert!(overlap(&atlas.uvs, &atlas.indices, 64).is_none());
        assert!(atlas.rejected_uv1.as_deref().is_some_and(|r| r.contains("covered twice")), "{:?}", atlas.rejected_uv1);
    }

    #[test]
    fn torus_uvs_are_kept() {
        let torus = shapes::torus(0.8, 0.3, 24, 12).expect("torus");
        assert_eq!(mesh_atlas("torus", &torus, None, 256).expect("atlas").source, AtlasSource::TexCoord0);
    }
}
