// Per-draw values (80 of the profile's 128 push-constant bytes).
layout(push_constant) uniform ObjectPush {
    mat4 model;
    // rgb: albedo; a: the alpha this draw writes (the emulated stencil's initial value).
    vec4 colour;
} object;
