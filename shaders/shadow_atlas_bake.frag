#version 450
// Atlas bake: per channel R, G, B the visibility of the light it holds (shadow.channels; 1 lit,
// 0 shadowed, 1 for a channel no light holds); alpha 1 marks a texel the surface covers. One
// pass reads every light's map: each model is rasterised once per bake rather than once per
// light, and a texel is written whole (no write mask per channel).
#define LIGHT_SET 0
#include "shadow_atlas_light.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;

layout(location = 0) out vec4 out_texel;

void main() {
    vec3 visible = vec3(1.0);
    for (int c = 0; c < 3; ++c) {
        int light = shadow.channels[c];
        float v = shadow_visibility(max(light, 0), world_position, world_normal);
        visible[c] = light >= 0 ? v : 1.0;
    }
    out_texel = vec4(visible, 1.0);
}
