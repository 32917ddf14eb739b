#version 450
// Projective bake: each triangle drawn where the primary light sees it (the shadow map's projection),
// carrying its world position and normal to the fragment shader.
#define LIGHT_SET 0
#include "shadow_atlas_light.glsl"
#include "object_push.glsl"

#include "atlas_vertex.glsl"

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;

void main() {
    vec4 world = object.model * vec4(in_position, 1.0);
    world_position = world.xyz;
    world_normal = transpose(inverse(mat3(object.model))) * in_normal;
    gl_Position = shadow.lights[shadow.primary.x].view_proj * world;
}
