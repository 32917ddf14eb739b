#version 450
// The atlas page pass over a rasterised model's tile: its raw bake (the raw page) dilated
// within its own tile (atlas_dilate.glsl), one fragment per texel.
#include "atlas_dilate.glsl"

layout(set = 2, binding = 0) uniform sampler2D raw_bake;

layout(location = 0) flat in ivec4 rect;
layout(location = 1) flat in int radius;

layout(location = 0) out vec4 out_texel;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    out_texel = dilated(raw_bake, p, rect.xy, rect.xy + rect.z, radius);
}
