#version 450
// Scene pass of the shadow techniques: world position and normal, the atlas UV, and the
// material's inputs.
// twin: skinned
#include "frame_uniforms.glsl"
#include "object_push.glsl"

#include "atlas_vertex.glsl"
#include "object_vertex.glsl"

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec2 atlas_uv;
layout(location = 3) out vec2 uv0;
layout(location = 4) out vec2 uv1;
layout(location = 5) out vec4 vertex_colour;

void main() {
    ObjectVertex vertex = object_vertex();
    vec4 world = object.model * vertex.position;
    world_position = world.xyz;
    world_normal = transpose(inverse(mat3(object.model))) * vertex.normal;
    atlas_uv = in_atlas_uv;
    uv0 = in_uv0;
    uv1 = in_uv1;
    vertex_colour = in_colour;
    gl_Position = frame.view_proj * world;
}
