#version 450
// The atlas page pass over geometry images' tiles (atlas_page_quad.glsl): the tile's placement
// and model matrix, for its texels' surface points.
#include "atlas_page_quad.glsl"

layout(location = 0) flat out ivec4 rect;
layout(location = 2) flat out mat4 model;
layout(location = 6) flat out mat3 normal_matrix;

void main() {
    int tile = gl_InstanceIndex;
    rect = tiles[tile].rect;
    model = tiles[tile].model;
    normal_matrix = transpose(inverse(mat3(model)));
    gl_Position = tile_corner(tile);
}
