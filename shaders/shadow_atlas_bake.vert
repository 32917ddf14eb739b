#version 450
// Atlas bake: each triangle is drawn where it lies in the model's atlas (uv * 2 - 1), carrying
// its world position and normal to the fragment shader. Sets: the frame's (its joint
// palettes), the lights.
// twin: skinned
#define LIGHT_SET 1
#include "shadow_atlas_light.glsl"
#include "object_push.glsl"

#include "atlas_vertex.glsl"
#include "object_vertex.glsl"

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;

void main() {
    ObjectVertex vertex = object_vertex();
    world_position = (object.model * vertex.position).xyz;
    world_normal = transpose(inverse(mat3(object.model))) * vertex.normal;
    gl_Position = vec4(in_atlas_uv * 2.0 - 1.0, 0.0, 1.0);
}
