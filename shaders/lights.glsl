// What each light adds to a surface (Lambert), following KHR_lights_punctual: colour x
// intensity, the spec's recommended range window and inverse-square falloff for point and
// spot lights, and the spot cone's smooth edge. Written without a branch on a uniform (see
// toward_light.glsl): a directional light's terms come out as exactly 1.
#ifndef LIGHTS_GLSL
#define LIGHTS_GLSL
#include "frame_uniforms.glsl"

// How many lights the forward passes sum: the scene's count, set when the pipeline is built
// (a loop bound read from a uniform would be a branch on it).
layout(constant_id = 1) const int LIGHT_COUNT = 1;

// The light `light`'s radiance arriving at `world_position` on a surface of unit normal `n`,
// times N.L.
vec3 light_contribution(FrameLight light, vec3 world_position, vec3 n) {
    vec3 to_light = toward_light(light.position, world_position);
    float d2 = dot(to_light, to_light);
    vec3 l = normalize(to_light);
    float n_dot_l = max(dot(n, l), 0.0);
    // 1 / d^2 for positional lights (w = 1), exactly 1 for directional ones (w = 0).
    float inv_square = 1.0 / mix(1.0, max(d2, 1e-4), light.position.w);
    // KHR: clamp(1 - (d / range)^4, 0, 1); 1 / range is 0 without a range.
    float d_over_range = sqrt(d2) * light.direction.w;
    float window = clamp(1.0 - d_over_range * d_over_range * d_over_range * d_over_range, 0.0, 1.0);
    float cone = clamp(dot(light.direction.xyz, -l) * light.cone.x + light.cone.y, 0.0, 1.0);
    return light.radiance.rgb * (n_dot_l * inv_square * window * (cone * cone));
}

// Ambient plus every light: the lighting factor of a pass that shades all lights at once.
vec3 all_lights(vec3 world_position, vec3 n) {
    vec3 sum = vec3(frame.shading.x);
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        sum += light_contribution(frame.lights[i], world_position, n);
    }
    return sum;
}
#endif
