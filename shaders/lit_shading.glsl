// Included by lit.frag and its material variants (lit_masked.frag: ALPHA_MASK,
// lit_blend.frag: ALPHA_BLEND), and the additive loop's ambient pass (lit_ambient*.frag:
// AMBIENT_ONLY).
// Lambert + ambient on the material's surface, every light of the frame summed. Alpha is not
// lighting: it is the emulated stencil's starting value (the draw's), whatever the material's
// alpha.
#include "lights.glsl"
#include "object_push.glsl"
#include "material.glsl"

#include "lit_inputs.glsl"

void main() {
    vec4 base = material_surface(uv0, uv1, vertex_colour);
    vec3 n = surface_normal(world_normal);
#ifdef AMBIENT_ONLY
    vec3 light = vec3(frame.shading.x);
#else
    vec3 light = all_lights(world_position, n);
#endif
    out_colour = vec4(material_shade(base, light, uv0, uv1), written_alpha(base));
}
