// The atlas page pass's quads (shadow_atlas_page.vert, shadow_atlas_page_dilate.vert): one per
// tile re-baked (instance = tile index, from firstInstance), covering the tile's texels of the
// page. What the fragments need of the tile is handed down flat, once a vertex: the fragment
// shader then reads only its texel's surface point (a storage-buffer read per value is a
// gather per lane on a software rasteriser).
#include "atlas_page_tiles.glsl"

layout(push_constant) uniform Page {
    // xy: the page's size in texels.
    vec4 size;
} page;

// Corner gl_VertexIndex of tile `tile`'s square (two triangles: corners 0 1 2, 2 1 3).
vec4 tile_corner(int tile) {
    ivec4 rect = tiles[tile].rect;
    int corner = int[6](0, 1, 2, 2, 1, 3)[gl_VertexIndex];
    vec2 texel = vec2(rect.xy) + vec2(corner & 1, corner >> 1) * float(rect.z);
    return vec4(texel / page.size.xy * 2.0 - 1.0, 0.0, 1.0);
}
