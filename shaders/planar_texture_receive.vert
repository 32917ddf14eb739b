#version 450
// Shadow texture: a receiver drawn again, carrying its position in the light's clip space.
#include "frame_uniforms.glsl"

layout(push_constant) uniform ReceivePush {
    mat4 model;
    mat4 light_view_proj;
} receive;

#include "scene_vertex.glsl"

layout(location = 0) out vec4 light_clip;

void main() {
    vec4 world = receive.model * vec4(in_position, 1.0);
    light_clip = receive.light_view_proj * world;
    gl_Position = frame.view_proj * world;
}
