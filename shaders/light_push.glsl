// Per-draw values of a per-light pass (96 of the profile's 128 push-constant bytes): the object's
// (object_push.glsl) and which of the frame's lights the pass adds. The light itself (64 bytes)
// stays in the frame's uniforms: 80 + 64 would pass the profile's limit.
layout(push_constant) uniform LightPush {
    mat4 model;
    // rgb: albedo; a: the alpha this draw writes.
    vec4 colour;
    // x: index into frame.lights.
    uvec4 light;
} object;
