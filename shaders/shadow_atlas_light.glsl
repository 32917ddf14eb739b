// The light's shadow map and how it is compared (shared by the shadow-map pass, the atlas bake
// and the shadow-map scene pass). Set LIGHT_SET, bindings 0 and 1.
#include "toward_light.glsl"

layout(set = LIGHT_SET, binding = 0) uniform ShadowLight {
    mat4 view_proj;
    // xyz: direction the light travels (w = 0) or light position (w = 1).
    vec4 light;
    // x: constant bias, y: slope-scaled bias (both in shadow-map depth units), z: largest slope.
    vec4 bias;
} shadow;

layout(set = LIGHT_SET, binding = 1) uniform sampler2DShadow shadow_map;

// 1: lit, 0: in shadow. Surfaces facing away from the light are in their own shadow. Points
// outside the map are lit. The depth compare is the sampler's (hardware), with a slope-scaled
// bias from the angle between the normal and the light.
float shadow_visibility(vec3 world_position, vec3 world_normal) {
    vec3 to_light = toward_light(shadow.light, world_position);
    float n_dot_l = dot(normalize(world_normal), normalize(to_light));
    if (n_dot_l <= 0.0) {
        return 0.0;
    }
    vec4 clip = shadow.view_proj * vec4(world_position, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (clip.w <= 0.0 || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || ndc.z > 1.0) {
        return 1.0;
    }
    float tan_angle = sqrt(max(1.0 - n_dot_l * n_dot_l, 0.0)) / n_dot_l;
    float bias = shadow.bias.x + shadow.bias.y * min(tan_angle, shadow.bias.z);
    return texture(shadow_map, vec3(uv, ndc.z - bias));
}
