#version 450
// Atlas bake: per channel R, G, B the visibility of the light it holds (shadow.channels; 1 lit,
// 0 shadowed, 1 for a channel no light holds); alpha 1 marks a texel the surface covers. One
// pass reads every light's map: each model is rasterised once per bake rather than once per
// light, and a texel is written whole (no write mask per channel).
#define LIGHT_SET 1
#include "shadow_atlas_light.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;

layout(location = 0) out vec4 out_texel;

// The scene's lights (specialization constant 1): the loop unrolls, so each light's uniforms are
// read at constant offsets (see shadow_atlas_page.frag, whose texels this bake must equal).
layout(constant_id = 1) const int LIGHT_COUNT = 1;

void main() {
    vec3 visible = vec3(1.0);
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        float v = shadow_visibility(i, world_position, world_normal);
        for (int c = 0; c < 3; ++c) {
            visible[c] = shadow.channels[c] == i ? v : visible[c];
        }
    }
    out_texel = vec4(visible, 1.0);
}
