#version 450
// Projective bake: each triangle drawn where the primary light sees it (the shadow map's projection),
// carrying its world position and normal to the fragment shader. Sets: the frame's (its joint
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
    vec4 world = object.model * vertex.position;
    world_position = world.xyz;
    world_normal = transpose(inverse(mat3(object.model))) * vertex.normal;
    gl_Position = shadow.lights[shadow.primary.x].view_proj * world;
}
