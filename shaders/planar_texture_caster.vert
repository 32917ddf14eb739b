#version 450
// Shadow texture: a caster drawn from the light; `object.model` is light_view_proj * model.
#include "object_push.glsl"

#include "scene_vertex.glsl"

void main() {
    gl_Position = object.model * vec4(in_position, 1.0);
}
