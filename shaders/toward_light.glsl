// The vector from `world_position` towards a light given as xyz = direction the light travels
// (w = 0) or xyz = its position (w = 1). Written without a branch on w: lavapipe (Mesa 22.x)
// "inlines" a uniform that decides a branch, compiling a new shader variant each time the
// pipeline is bound and never freeing the old one, so a per-object bake pass grew its memory by
// megabytes a frame. Exact for w in {0, 1}: the products are by 0 and +-1.
#ifndef TOWARD_LIGHT_GLSL
#define TOWARD_LIGHT_GLSL
vec3 toward_light(vec4 light, vec3 world_position) {
    return light.xyz * (2.0 * light.w - 1.0) - world_position * light.w;
}
#endif
