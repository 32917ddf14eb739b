#version 450
// Ink lines as screen-space quads (the mobile profile has no wideLines). Each edge is six
// vertices carrying both world-space end points; the quad is built in pixels from their
// projections, so its width is `params.x` pixels wherever the edge is.
//   corner.x: -1 or +1, the side of the edge; corner.y: 0 at end a, 1 at end b.
// Silhouettes (params.y = 1) grow only outwards, away from `c` (the third corner of the
// front-facing face): the inner half would lie on the surface that curves towards the eye
// next to a silhouette and fail the depth test. Other edges are centred on the edge.
// Ends are extended by half the width (square caps), so consecutive edges join without gaps.
#include "frame_uniforms.glsl"
#include "cartoon_push.glsl"

layout(location = 0) in vec3 in_a;
layout(location = 1) in vec3 in_b;
layout(location = 2) in vec3 in_c;
layout(location = 3) in vec2 in_corner;

void main() {
    vec4 ca = frame.view_proj * vec4(in_a, 1.0);
    vec4 cb = frame.view_proj * vec4(in_b, 1.0);
    vec2 half_viewport = 0.5 * object.viewport.xy;
    vec2 sa = ca.xy / ca.w * half_viewport;
    vec2 sb = cb.xy / cb.w * half_viewport;
    vec2 along = sb - sa;
    float len = length(along);
    vec2 dir = len > 1e-6 ? along / len : vec2(1.0, 0.0);
    vec2 across = vec2(-dir.y, dir.x);
    float half_width = 0.5 * object.params.x;

    float centre = 0.0;
    if (object.params.y > 0.5) {
        vec4 cc = frame.view_proj * vec4(in_c, 1.0);
        vec2 sc = cc.xy / cc.w * half_viewport;
        float inside = dot(sc - sa, across) >= 0.0 ? 1.0 : -1.0;
        centre = -inside * half_width;
    }
    bool at_a = in_corner.y < 0.5;
    vec4 base = at_a ? ca : cb;
    vec2 offset = across * (in_corner.x * half_width + centre) + dir * (at_a ? -half_width : half_width);
    // Pulled towards the eye by a fixed fraction of its distance (params.z = near * fraction:
    // with the infinite-far projection, clip z = INFINITY_DEPTH * w - near).
    gl_Position = vec4(base.xy + offset / half_viewport * base.w, base.z - object.params.z, base.w);
}
