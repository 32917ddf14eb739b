// Included by lit_light.frag and lit_light_masked.frag (ALPHA_MASK): one light's contribution
// to an opaque or cut-out surface, for the additive loop's `L: shading` pass (depth EQUAL). No
// ambient and no emissive (the ambient pass drew them); an unlit material adds nothing. Alpha
// out is 1: with blend factors (DST_ALPHA, ONE) on colour and (ONE, ZERO) on alpha, the pass adds
// the light where the shadow mask holds 1 and resets the counter for the next light.
#include "lights.glsl"
#include "light_push.glsl"
#include "material.glsl"

#include "lit_inputs.glsl"

void main() {
    vec4 base = material_surface(uv0, uv1, vertex_colour);
    vec3 n = surface_normal(world_normal);
    vec3 light = light_contribution(frame.lights[object.light.x], world_position, n);
    vec3 lit = material.params.y > 0.5 ? vec3(0.0) : base.rgb * light;
    out_colour = vec4(lit, 1.0);
}
