#version 450
// Shadow texture: a skinned caster drawn from the light; `object.model` is light_view_proj * model.
#include "object_push.glsl"
#include "planar_skinning.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in uvec4 in_joints;
layout(location = 3) in vec4 in_weights;

void main() {
    gl_Position = object.model * (skin_matrix(in_joints, in_weights) * vec4(in_position, 1.0));
}
