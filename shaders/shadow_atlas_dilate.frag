#version 450
// Dilation of one model's raw bake into its own shadow texture (the projective texture: radius
// 0, a copy). See atlas_dilate.glsl.
#include "atlas_dilate.glsl"

layout(set = 0, binding = 0) uniform sampler2D baked;

layout(push_constant) uniform Dilate {
    ivec4 params; // x: radius in texels
} dilate;

layout(location = 0) out vec4 out_texel;

void main() {
    out_texel = dilated(baked, ivec2(gl_FragCoord.xy), ivec2(0), textureSize(baked, 0), dilate.params.x);
}
