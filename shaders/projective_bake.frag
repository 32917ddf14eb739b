#version 450
// Projective bake: a texel of the light's view is shadowed (0) when any surface of the model on
// its light ray faces the light and is in shadow; the texture is cleared to lit, so lit and
// back-facing surfaces write nothing. One texel cannot tell the surfaces on its ray apart: the
// lit surface in front of a shadowed one takes its shadow (the paper's figure 2).
#define LIGHT_SET 1
#include "shadow_atlas_light.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;

layout(location = 0) out vec4 out_texel;

void main() {
    int primary = shadow.primary.x;
    vec3 to_light = toward_light(shadow.lights[primary].light, world_position);
    if (dot(world_normal, to_light) <= 0.0 || shadow_weight(primary, world_position, world_normal) > 0.5) {
        discard;
    }
    out_texel = vec4(0.0, 0.0, 0.0, 1.0);
}
