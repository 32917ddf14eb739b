// Included by shadow_map_scene*.frag (SHADOW_FROM_MAP defined), projective_scene*.frag
// (SHADOW_PROJECTIVE defined) and shadow_atlas_scene*.frag, and their material variants
// (ALPHA_MASK, ALPHA_BLEND).
// Lambert + ambient on the material's surface, each light's term scaled by its visibility:
// the shadow map's depth compare in the light's layer (every light with a map), the model's
// baked shadow texture in the light's channel (trilinear; the lights the bake holds), or the
// model's shadow texture projected from the primary light (that light alone). Lights without
// a shadow shade unshadowed.
#include "lights.glsl"
#include "object_push.glsl"
#include "material.glsl"
#ifdef SHADOW_FROM_MAP
#define LIGHT_SET 2
#include "shadow_atlas_light.glsl"
#elif defined(SHADOW_PROJECTIVE)
layout(set = 2, binding = 0) uniform sampler2D shadow_texture;
#define LIGHT_SET 3
#include "shadow_atlas_light.glsl"
#else
#include "atlas_page_sample.glsl"
#define LIGHT_SET 3
#include "shadow_atlas_light.glsl"
#endif

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in vec2 atlas_uv;
layout(location = 3) in vec2 uv0;
layout(location = 4) in vec2 uv1;
layout(location = 5) in vec4 vertex_colour;

layout(location = 0) out vec4 out_colour;

void main() {
    vec4 base = material_surface(uv0, uv1, vertex_colour);
    vec3 n = surface_normal(world_normal);
#if defined(SHADOW_PROJECTIVE)
    int primary = shadow.primary.x;
    vec4 light_clip = shadow.lights[primary].view_proj * vec4(world_position, 1.0);
    float projected = texture(shadow_texture, light_clip.xy / light_clip.w * 0.5 + 0.5).r;
#elif !defined(SHADOW_FROM_MAP)
    vec4 baked = sample_tile(atlas_uv);
#endif
    vec3 light = vec3(frame.shading.x);
    for (int i = 0; i < LIGHT_COUNT; ++i) {
#if defined(SHADOW_FROM_MAP)
        float weight = shadow_weight(i, world_position, world_normal);
#elif defined(SHADOW_PROJECTIVE)
        float weight = i == primary ? projected : 1.0;
#else
        // The channel the bake holds light i in, if any (selects, no branch on a uniform).
        float weight = 1.0;
        for (int c = 0; c < 3; ++c) {
            weight = shadow.channels[c] == i ? baked[c] : weight;
        }
#endif
        light += light_contribution(frame.lights[i], world_position, n) * weight;
    }
    out_colour = vec4(material_shade(base, light, uv0, uv1), written_alpha(base));
}
