#version 450
// The lit scene pass for a skinned object: skinned on the GPU, then as lit.vert. The material
// is set 1, so the palette moves to set 2.
#include "frame_uniforms.glsl"
#include "object_push.glsl"
#define PALETTE_SET 2
#include "planar_skinning.glsl"
#include "skinned_vertex.glsl"

// Invariant: each light's shading pass meets the ambient pass's depth with depth EQUAL.
invariant gl_Position;

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out vec2 uv0;
layout(location = 3) out vec2 uv1;
layout(location = 4) out vec4 vertex_colour;

void main() {
    mat4 skin = skin_matrix(in_joints, in_weights);
    vec4 world = object.model * (skin * vec4(in_position, 1.0));
    world_position = world.xyz;
    // Inverse-transpose of model * skin: right under non-uniform scale, as on the CPU.
    world_normal = transpose(inverse(mat3(object.model))) * (transpose(inverse(mat3(skin))) * in_normal);
    uv0 = in_uv0;
    uv1 = in_uv1;
    vertex_colour = in_colour;
    gl_Position = frame.view_proj * world;
}
