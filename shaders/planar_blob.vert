#version 450
// Blob shadow: a quad lying on the ground plane under a caster (world-space vertices).
#include "frame_uniforms.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec2 in_uv;
// How dark the blob's centre is (0..1): fades with the caster's height above the ground.
layout(location = 2) in float in_strength;

layout(location = 0) out vec2 uv;
layout(location = 1) out float strength;

void main() {
    uv = in_uv;
    strength = in_strength;
    gl_Position = frame.view_proj * vec4(in_position, 1.0);
}
