#version 450
// The atlas page pass over rasterised tiles (atlas_page_quad.glsl): the tile's placement and
// dilation radius.
#include "atlas_page_quad.glsl"

layout(location = 0) flat out ivec4 rect;
layout(location = 1) flat out int radius;

void main() {
    int tile = gl_InstanceIndex;
    rect = tiles[tile].rect;
    radius = tiles[tile].params.x;
    gl_Position = tile_corner(tile);
}
