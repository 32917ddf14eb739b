#version 450
// Shadow-map pass: casters seen from the light, depth only.
#define LIGHT_SET 0
#include "shadow_atlas_light.glsl"
#include "object_push.glsl"

layout(location = 0) in vec3 in_position;
// The scene's vertex buffers, shared with the other passes: normal and atlas UV unused here.
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_atlas_uv;

void main() {
    gl_Position = shadow.view_proj * (object.model * vec4(in_position, 1.0));
}
