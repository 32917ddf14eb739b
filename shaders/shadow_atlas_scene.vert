#version 450
// Scene pass of the shadow techniques: world position and normal, and the atlas UV.
#include "frame_uniforms.glsl"
#include "object_push.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_atlas_uv;

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec2 atlas_uv;

void main() {
    vec4 world = object.model * vec4(in_position, 1.0);
    world_position = world.xyz;
    world_normal = transpose(inverse(mat3(object.model))) * in_normal;
    atlas_uv = in_atlas_uv;
    gl_Position = frame.view_proj * world;
}
