#version 450
// The atlas page pass: one quad per tile re-baked (instance = tile index, from firstInstance),
// covering the tile's texels of the page. What the fragments need of the tile is handed down
// flat, once a vertex: the fragment shader then reads only its texel's surface point (a
// storage-buffer read per value is a gather per lane on a software rasteriser).
#include "atlas_page_tiles.glsl"

layout(push_constant) uniform Page {
    // xy: the page's size in texels; z: the baked channels (lights with a map, at most 3).
    vec4 size;
} page;

layout(location = 0) flat out ivec4 rect;
layout(location = 1) flat out int radius;
layout(location = 2) flat out mat4 model;
layout(location = 6) flat out mat3 normal_matrix;

void main() {
    int tile = gl_InstanceIndex;
    rect = tiles[tile].rect;
    radius = tiles[tile].params.x;
    model = tiles[tile].model;
    normal_matrix = transpose(inverse(mat3(model)));
    // Two triangles: corners 0 1 2, 2 1 3 of the tile's square.
    int corner = int[6](0, 1, 2, 2, 1, 3)[gl_VertexIndex];
    vec2 texel = vec2(rect.xy) + vec2(corner & 1, corner >> 1) * float(rect.z);
    gl_Position = vec4(texel / page.size.xy * 2.0 - 1.0, 0.0, 1.0);
}
