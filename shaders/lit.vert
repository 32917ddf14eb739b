#version 450
// Scene geometry: world position and normal for Lambert shading, and the material's inputs.
// twin: skinned
#include "frame_uniforms.glsl"
#include "object_push.glsl"
#include "scene_vertex.glsl"
#include "object_vertex.glsl"

// Invariant: shadow-volume caps reuse these positions and must land on the same depths.
invariant gl_Position;

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec2 uv0;
layout(location = 3) out vec2 uv1;
layout(location = 4) out vec4 vertex_colour;

void main() {
    ObjectVertex vertex = object_vertex();
    vec4 world = object.model * vertex.position;
    world_position = world.xyz;
    // Inverse-transpose keeps normals right under non-uniform scale.
    world_normal = transpose(inverse(mat3(object.model))) * vertex.normal;
    uv0 = in_uv0;
    uv1 = in_uv1;
    vertex_colour = in_colour;
    gl_Position = frame.view_proj * world;
}
