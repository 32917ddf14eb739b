#version 450
// The draw's push-constant colour as is: for counting passes, alpha = k / 255.
#include "object_push.glsl"

layout(location = 0) out vec4 out_colour;

void main() {
    out_colour = object.colour;
}
