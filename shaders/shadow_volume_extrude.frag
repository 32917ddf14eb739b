#version 450
// A volume extruded on the GPU counts |m| times k / 255 where its CPU twin draws a wall of
// multiplicity m with alpha m k / 255 (one product in both, so the same float).
#include "volume_push.glsl"

layout(location = 0) flat in float weight;
layout(location = 0) out vec4 out_colour;

void main() {
    out_colour = vec4(object.colour.rgb, object.colour.a * weight);
}
