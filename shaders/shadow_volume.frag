#version 450
// A volume's fragment counts |m| times k / 255, |m| the multiplicity of the wall or cap it lies
// on, which both vertex shaders pass as `weight`: shadow_volume.vert from the draw's first
// instance (one push serves every range of a volume), shadow_volume_extrude.vert from its tables.
#include "volume_push.glsl"

layout(location = 0) flat in float weight;
layout(location = 0) out vec4 out_colour;

void main() {
    out_colour = vec4(object.colour.rgb, object.colour.a * weight);
}
