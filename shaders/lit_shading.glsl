// Included by lit.frag and its material variants (lit_masked.frag: ALPHA_MASK,
// lit_blend.frag: ALPHA_BLEND).
// Lambert + ambient on the material's surface. Alpha is not lighting: it is the emulated
// stencil's starting value (the draw's), whatever the material's alpha.
#include "frame_uniforms.glsl"
#include "object_push.glsl"
#include "material.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in vec2 uv0;
layout(location = 3) in vec2 uv1;
layout(location = 4) in vec4 vertex_colour;

layout(location = 0) out vec4 out_colour;

void main() {
    vec4 base = material_surface(uv0, uv1, vertex_colour);
    vec3 n = surface_normal(world_normal);
    float lambert = frame_lambert(world_position, n);
    float ambient = frame.shading.x;
    out_colour = vec4(material_shade(base, vec3(ambient + (1.0 - ambient) * lambert), uv0, uv1), written_alpha(base));
}
