// A shadow caster's MASK cut-out: texels of its material below the cutoff cast no shadow.
#include "material.glsl"

layout(location = 0) in vec2 uv0;
layout(location = 1) in vec2 uv1;
layout(location = 2) in vec4 vertex_colour;

void cut_out() {
    if (material_cut(material_base(uv0, uv1, vertex_colour))) {
        discard;
    }
}
