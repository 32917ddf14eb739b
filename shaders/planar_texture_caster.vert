#version 450
// Shadow texture: a caster drawn from the light; `object.model` is light_view_proj * model.
#include "object_push.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

void main() {
    gl_Position = object.model * vec4(in_position, 1.0);
}
