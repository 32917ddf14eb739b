#version 450
// twin: skinned
// Shadow texture: a caster drawn from the light; `object.model` is light_view_proj * model.
#include "object_push.glsl"

#include "scene_vertex.glsl"
#include "object_vertex.glsl"

void main() {
    gl_Position = object.model * object_vertex().position;
}
