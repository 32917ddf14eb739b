#version 450
// A skinned object flattened onto the receiving plane: skinning first, then the projection.
#include "frame_uniforms.glsl"
#include "planar_push.glsl"
#include "planar_project.glsl"
#include "planar_skinning.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in uvec4 in_joints;
layout(location = 3) in vec4 in_weights;

void main() {
    vec3 world = (planar.model * (skin_matrix(in_joints, in_weights) * vec4(in_position, 1.0))).xyz;
    gl_Position = frame.view_proj * vec4(project_onto_plane(world, frame.light, planar.plane.x), 1.0);
}
