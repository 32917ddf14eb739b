// The atlas page's tiles as the page pass reads them (shadow_atlas::page_targets::TileRecord),
// and the surface points of the geometry images' texels (texel_surface.rs). Set 1.
#ifndef ATLAS_PAGE_TILES_GLSL
#define ATLAS_PAGE_TILES_GLSL
struct PageTile {
    mat4 model;
    // x, y: the tile's corner in the page (texels of mip 0); z: its side; w: where its texels'
    // surface points start in `surface` (two vec4 a texel), -1 for a tile dilated from the raw
    // bake (a mesh rasterised at its atlas UVs).
    ivec4 rect;
    // x: the dilation radius (rasterised tiles).
    ivec4 params;
};

layout(std430, set = 1, binding = 0) readonly buffer PageTiles {
    PageTile tiles[];
};

layout(std430, set = 1, binding = 1) readonly buffer TexelSurface {
    // Per texel: object-space position (w 1), then normal (w 0).
    vec4 surface[];
};
#endif
