#version 450
// A skinned MASK caster flattened onto the receiving plane (planar_shadow_skinned.vert), with
// the material's inputs for the cut-out.
#include "frame_uniforms.glsl"
#include "planar_push.glsl"
#include "planar_project.glsl"
#define PALETTE_SET 2
#include "planar_skinning.glsl"
#include "skinned_vertex.glsl"
#include "material_out.glsl"

void main() {
    pass_material_inputs();
    vec3 world = (planar.model * (skin_matrix(in_joints, in_weights) * vec4(in_position, 1.0))).xyz;
    gl_Position = frame.view_proj * vec4(project_onto_plane(world, frame.lights[planar.light.x].position, planar.plane), 1.0);
}
