// The lights' shadow maps and how they are compared (shared by the shadow-map passes, the
// atlas bake, the projective bake and the scene passes). Set LIGHT_SET, bindings 0 and 1.
#include "toward_light.glsl"

// The frame's lights (MAX_LIGHTS in frame_uniforms.glsl).
#define SHADOW_LIGHTS 8

// One scene light as the shadow passes see it (shadow_atlas::light::ShadowLight).
struct ShadowLight {
    mat4 view_proj;
    // xyz: direction the light travels (w = 0) or light position (w = 1).
    vec4 light;
    // x: constant bias, y: slope-scaled bias (both in shadow-map depth units), z: largest slope.
    vec4 bias;
    // x: the light's layer of the map array, -1 without a map.
    ivec4 slot;
};

layout(set = LIGHT_SET, binding = 0) uniform ShadowLights {
    // By the scene's light index.
    ShadowLight lights[SHADOW_LIGHTS];
    // x: the primary light's index (the projective texture's one light).
    ivec4 primary;
    // Per channel R, G, B of a baked texel: the light it holds, -1 for none.
    ivec4 channels;
} shadow;

// One layer per shadowing light.
layout(set = LIGHT_SET, binding = 1) uniform sampler2DArrayShadow shadow_map;

// Light `i`'s visibility: 1 lit, 0 in shadow. Surfaces facing away from the light are in their
// own shadow. Points outside the light's map are lit. The depth compare is the sampler's
// (hardware), with a slope-scaled bias from the angle between the normal and the light. A
// light without a map (slot.x -1) reads layer 0: callers weight by `has_shadow_map` first.
float shadow_visibility(int i, vec3 world_position, vec3 world_normal) {
    vec3 to_light = toward_light(shadow.lights[i].light, world_position);
    float n_dot_l = dot(normalize(world_normal), normalize(to_light));
    if (n_dot_l <= 0.0) {
        return 0.0;
    }
    vec4 clip = shadow.lights[i].view_proj * vec4(world_position, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (clip.w <= 0.0 || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || ndc.z > 1.0) {
        return 1.0;
    }
    vec4 bias = shadow.lights[i].bias;
    float tan_angle = sqrt(max(1.0 - n_dot_l * n_dot_l, 0.0)) / n_dot_l;
    float layer = float(max(shadow.lights[i].slot.x, 0));
    return texture(shadow_map, vec4(uv, layer, ndc.z - (bias.x + bias.y * min(tan_angle, bias.z))));
}

// Light `i`'s weight: its visibility when it has a map, else 1 (unshadowed). Both sides are
// computed: a select, not a branch on a uniform (see toward_light.glsl).
float shadow_weight(int i, vec3 world_position, vec3 world_normal) {
    float visible = shadow_visibility(i, world_position, world_normal);
    return shadow.lights[i].slot.x >= 0 ? visible : 1.0;
}
