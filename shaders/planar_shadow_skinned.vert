#version 450
// A skinned object flattened onto the receiving plane: skinning first, then the projection.
#include "frame_uniforms.glsl"
#include "planar_push.glsl"
#include "planar_project.glsl"
#include "planar_skinning.glsl"

#include "skinned_vertex.glsl"

void main() {
    vec3 world = (planar.model * (skin_matrix(in_joints, in_weights) * vec4(in_position, 1.0))).xyz;
    gl_Position = frame.view_proj * vec4(project_onto_plane(world, frame.light, planar.plane.x), 1.0);
}
