#version 450
// A constant colour from push constants (also: a constant alpha for counter passes).
layout(push_constant) uniform SolidPush {
    vec4 colour;
} solid;

layout(location = 0) out vec4 out_colour;

void main() {
    out_colour = solid.colour;
}
