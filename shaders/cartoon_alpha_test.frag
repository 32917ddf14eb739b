#version 450
// Dietrich's alpha-test silhouette (seed 002, "advanced texturing"): N.V of the interpolated
// normal and the view vector, both normalised per pixel (what the original's normalisation cube
// map does), is the alpha; the alpha test keeps the pixels at most `params.x` (LESS_EQUAL) and
// paints them in ink. Vulkan has no alpha test: `discard` is it. A larger reference value
// keeps more of the surface near the contour: a thicker line.
#include "frame_uniforms.glsl"
#include "cartoon_push.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in float facing;
layout(location = 3) in vec2 uv0;
layout(location = 4) in vec2 uv1;
layout(location = 5) in vec4 vertex_colour;

layout(location = 0) out vec4 out_colour;

void main() {
    vec3 n = normalize(world_normal);
    vec3 v = normalize(frame.camera_position.xyz - world_position);
    float alpha = dot(n, v);
    if (alpha > object.params.x) {
        discard;
    }
    out_colour = vec4(object.colour.rgb, alpha);
}
