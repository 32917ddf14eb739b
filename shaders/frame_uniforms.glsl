// Per-frame values shared by every scene pass (set 0, binding 0).
#include "toward_light.glsl"

layout(set = 0, binding = 0) uniform FrameUniforms {
    mat4 view_proj;
    // xyz: direction the light travels (w = 0) or light position (w = 1).
    vec4 light;
    vec4 camera_position;
    // x: ambient term of the Lambert shading.
    vec4 shading;
} frame;

// Lambert's cosine between the unit normal `n` and the direction to the frame's light
// (directional or point), clamped at 0.
float frame_lambert(vec3 world_position, vec3 n) {
    vec3 to_light = toward_light(frame.light, world_position);
    return max(dot(n, normalize(to_light)), 0.0);
}
