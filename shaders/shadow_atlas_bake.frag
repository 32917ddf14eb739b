#version 450
// Atlas bake: lit (1) or shadowed (0) in red, alpha 1 marks a texel the surface covers.
#define LIGHT_SET 0
#include "shadow_atlas_light.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;

layout(location = 0) out vec4 out_texel;

void main() {
    float visible = shadow_visibility(world_position, world_normal);
    out_texel = vec4(visible, visible, visible, 1.0);
}
