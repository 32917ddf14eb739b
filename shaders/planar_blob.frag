#version 450
// Outputs the factor the pixel is multiplied by (colour blend ZERO, SRC_COLOR): 1 - strength x
// the blob texture's coverage.
layout(set = 1, binding = 0) uniform sampler2D blob;

layout(location = 0) in vec2 uv;
layout(location = 1) in float strength;

layout(location = 0) out vec4 out_factor;

void main() {
    float coverage = texture(blob, uv).a;
    out_factor = vec4(vec3(1.0 - strength * coverage), 1.0);
}
