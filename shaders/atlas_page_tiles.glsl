// The atlas page's tiles as the page pass reads them (shadow_atlas::page_targets::TileRecord),
// and the surface points of the geometry images' texels (texel_surface.rs). Set 1.
#ifndef ATLAS_PAGE_TILES_GLSL
#define ATLAS_PAGE_TILES_GLSL
struct PageTile {
    mat4 model;
    // x, y: the tile's corner in the page (texels of mip 0); z: its side; w: where its texels'
    // surface points start in `surface` (one uvec4 a texel), -1 for a tile dilated from the raw
    // bake (a mesh rasterised at its atlas UVs).
    ivec4 rect;
    // x: the dilation radius (rasterised tiles).
    ivec4 params;
};

layout(std430, set = 1, binding = 0) readonly buffer PageTiles {
    PageTile tiles[];
};

layout(std430, set = 1, binding = 1) readonly buffer TexelSurface {
    // Per texel (texel_surface::packed): the object-space position's bits in xyz, the
    // normal's direction in w (octahedral, two snorm16).
    uvec4 surface[];
};

vec3 texel_position(uvec4 texel) {
    return uintBitsToFloat(texel.xyz);
}

// The octahedral direction back on the sphere (unit length).
vec3 texel_normal(uvec4 texel) {
    vec2 e = unpackSnorm2x16(texel.w);
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    float t = max(-n.z, 0.0);
    n.xy += mix(vec2(t), vec2(-t), greaterThanEqual(n.xy, vec2(0.0)));
    return normalize(n);
}
#endif
