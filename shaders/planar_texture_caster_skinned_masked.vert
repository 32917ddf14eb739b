#version 450
// Shadow texture: a skinned MASK caster drawn from the light
// (planar_texture_caster_skinned.vert), with the material's inputs for the cut-out.
#include "object_push.glsl"
#define PALETTE_SET 2
#include "planar_skinning.glsl"
#include "skinned_vertex.glsl"
#include "material_out.glsl"

void main() {
    pass_material_inputs();
    gl_Position = object.model * (skin_matrix(in_joints, in_weights) * vec4(in_position, 1.0));
}
