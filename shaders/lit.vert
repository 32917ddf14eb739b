#version 450
// Scene geometry: world position and normal for Lambert shading.
#include "frame_uniforms.glsl"
#include "object_push.glsl"

// Invariant: shadow-volume caps reuse these positions and must land on the same depths.
invariant gl_Position;

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;

void main() {
    vec4 world = object.model * vec4(in_position, 1.0);
    world_position = world.xyz;
    // Inverse-transpose keeps normals right under non-uniform scale.
    world_normal = transpose(inverse(mat3(object.model))) * in_normal;
    gl_Position = frame.view_proj * world;
}
