#version 450
// A skinned object flattened onto the receiving plane: skinning first, then the projection.
#include "frame_uniforms.glsl"
#include "planar_push.glsl"
#include "planar_project.glsl"
// The material is set 1 of these passes, the palette set 2.
#define PALETTE_SET 2
#include "planar_skinning.glsl"

#include "skinned_vertex.glsl"

void main() {
    vec3 world = (planar.model * (skin_matrix(in_joints, in_weights) * vec4(in_position, 1.0))).xyz;
    gl_Position = frame.view_proj * vec4(project_onto_plane(world, frame.lights[planar.light.x].position, planar.plane), 1.0);
}
