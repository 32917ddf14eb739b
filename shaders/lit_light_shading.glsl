// Included by lit_light.frag and lit_light_masked.frag (ALPHA_MASK): one light's contribution
// to an opaque or cut-out surface, for the additive loop's `L: shading` pass (depth EQUAL). No
// ambient and no emissive (the ambient pass drew them); an unlit material adds nothing. Alpha
// out is 1: with blend factors (DST_ALPHA, ONE) on colour and (ONE, ZERO) on alpha, the pass adds
// the light where the shadow mask holds 1 and resets the counter for the next light.
#include "lights.glsl"
#include "light_push.glsl"
#include "material.glsl"

#include "lit_inputs.glsl"

#ifdef READS_COUNT
// `subpass` at one sample (lit_light_subpass*.frag): the light's volume count is read here, in
// place of a mask pass. A down-counter: alpha 1 is a count of 0. The blend is then (ONE, ONE)
// on colour and (ONE, ZERO) on alpha: nothing is added where the count is not 0, and alpha is
// reset to 1 for the next light all the same. Set 2: after the frame's uniforms and the material.
layout(input_attachment_index = 0, set = 2, binding = 0) uniform subpassInput counter;
#ifdef COUNTED
// Pixels whose counter sits at its clamp (alpha 0: a count of 255/k or more).
layout(set = 2, binding = 1, std430) buffer Saturation {
    uint saturated_samples;
} saturation;
#endif
#endif

void main() {
    vec4 base = material_surface(uv0, uv1, vertex_colour);
    vec3 n = surface_normal(world_normal);
    vec3 light = light_contribution(frame.lights[object.light.x], world_position, n);
    vec3 lit = material.params.y > 0.5 ? vec3(0.0) : base.rgb * light;
#ifdef READS_COUNT
    float count = subpassLoad(counter).a;
#ifdef COUNTED
    if (count <= 0.0) {
        atomicAdd(saturation.saturated_samples, 1u);
    }
#endif
    // Exactly the light, or exactly nothing.
    lit *= count >= 1.0 ? 1.0 : 0.0;
#endif
    out_colour = vec4(lit, 1.0);
}
