#version 450
// The lit scene pass for a skinned object: skinned on the GPU, then as lit.vert.
#include "frame_uniforms.glsl"
#include "object_push.glsl"
#include "planar_skinning.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in uvec4 in_joints;
layout(location = 3) in vec4 in_weights;

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;

void main() {
    mat4 skin = skin_matrix(in_joints, in_weights);
    vec4 world = object.model * (skin * vec4(in_position, 1.0));
    world_position = world.xyz;
    // Inverse-transpose of model * skin: right under non-uniform scale, as on the CPU.
    world_normal = transpose(inverse(mat3(object.model))) * (transpose(inverse(mat3(skin))) * in_normal);
    gl_Position = frame.view_proj * world;
}
