// Per-frame values shared by every scene pass (set 0, binding 0).
#include "toward_light.glsl"

#define MAX_LIGHTS 8

// One light (render::uniforms::GpuLight).
struct FrameLight {
    // xyz: position (w = 1) or the direction the light travels (w = 0).
    vec4 position;
    // xyz: a spot light's axis; w: 1 / range (0: the light has no range).
    vec4 direction;
    // rgb: colour x intensity.
    vec4 radiance;
    // x, y: KHR_lights_punctual's spot scale and offset ((0, 1) without a cone).
    vec4 cone;
};

layout(set = 0, binding = 0) uniform FrameUniforms {
    mat4 view_proj;
    // The primary light: xyz direction the light travels (w = 0) or its position (w = 1).
    vec4 light;
    vec4 camera_position;
    // x: ambient term; y: the number of lights.
    vec4 shading;
    FrameLight lights[MAX_LIGHTS];
} frame;

// Lambert's cosine between the unit normal `n` and the direction to the frame's primary light
// (directional or point), clamped at 0.
float frame_lambert(vec3 world_position, vec3 n) {
    vec3 to_light = toward_light(frame.light, world_position);
    return max(dot(n, normalize(to_light)), 0.0);
}
