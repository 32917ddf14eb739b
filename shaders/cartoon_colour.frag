#version 450
// The draw's push-constant colour (ink, outline).
#include "cartoon_push.glsl"

layout(location = 0) out vec4 out_colour;

void main() {
    out_colour = object.colour;
}
