// Per-frame values shared by every scene pass (set 0, binding 0).
layout(set = 0, binding = 0) uniform FrameUniforms {
    mat4 view_proj;
    // xyz: direction the light travels (w = 0) or light position (w = 1).
    vec4 light;
    vec4 camera_position;
    // x: ambient term of the Lambert shading.
    vec4 shading;
} frame;
