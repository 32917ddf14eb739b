#version 450
// object_colour.frag where the caster's material is not cut out (MASK).
#include "object_push.glsl"
#include "cut_out.glsl"

layout(location = 0) out vec4 out_colour;

void main() {
    cut_out();
    out_colour = object.colour;
}
