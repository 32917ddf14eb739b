// Included by shadow_map_scene*.frag (SHADOW_FROM_MAP defined), projective_scene*.frag
// (SHADOW_PROJECTIVE defined) and shadow_atlas_scene*.frag, and their material variants
// (ALPHA_MASK, ALPHA_BLEND).
// Lambert + ambient on the material's surface, the primary light's term scaled by its
// visibility: the shadow map's depth compare, the model's shadow texture projected from the
// light, or the model's baked shadow texture (trilinear).
#include "lights.glsl"
#include "object_push.glsl"
#include "material.glsl"
#ifdef SHADOW_FROM_MAP
#define LIGHT_SET 2
#include "shadow_atlas_light.glsl"
#else
layout(set = 2, binding = 0) uniform sampler2D shadow_texture;
#endif
#ifdef SHADOW_PROJECTIVE
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
#if defined(SHADOW_FROM_MAP)
    float visible = shadow_visibility(world_position, world_normal);
#elif defined(SHADOW_PROJECTIVE)
    vec4 light_clip = shadow.view_proj * vec4(world_position, 1.0);
    float visible = texture(shadow_texture, light_clip.xy / light_clip.w * 0.5 + 0.5).r;
#else
    float visible = texture(shadow_texture, atlas_uv).r;
#endif
    // The map or texture holds the primary light's visibility (frame.shading.z): it weights
    // that light alone; the others shade unshadowed.
    vec3 light = vec3(frame.shading.x);
    int shadowed = int(frame.shading.z);
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        float weight = i == shadowed ? visible : 1.0;
        light += light_contribution(frame.lights[i], world_position, n) * weight;
    }
    out_colour = vec4(material_shade(base, light, uv0, uv1), written_alpha(base));
}
