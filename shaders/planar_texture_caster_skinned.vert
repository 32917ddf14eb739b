#version 450
// Shadow texture: a skinned caster drawn from the light; `object.model` is light_view_proj * model.
#include "object_push.glsl"
// The material is set 1 of these passes, the palette set 2.
#define PALETTE_SET 2
#include "planar_skinning.glsl"

#include "skinned_vertex.glsl"

void main() {
    gl_Position = object.model * (skin_matrix(in_joints, in_weights) * vec4(in_position, 1.0));
}
