#version 450
// Lambert + ambient, the Lambert term scaled by the shadow map's depth compare.
#include "frame_uniforms.glsl"
#include "object_push.glsl"
#define LIGHT_SET 1
#include "shadow_atlas_light.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in vec2 atlas_uv;

layout(location = 0) out vec4 out_colour;

void main() {
    vec3 n = normalize(world_normal);
    vec3 to_light = frame.light.w == 0.0 ? -frame.light.xyz : frame.light.xyz - world_position;
    float lambert = max(dot(n, normalize(to_light)), 0.0);
    float visible = shadow_visibility(world_position, world_normal);
    float ambient = frame.shading.x;
    out_colour = vec4(object.colour.rgb * (ambient + (1.0 - ambient) * lambert * visible), object.colour.a);
}
