// Per-draw values of the projected shadow (112 of the profile's 128 push-constant bytes). The
// first 80 bytes are laid out as ObjectPush, which the fragment shader reads.
layout(push_constant) uniform PlanarPush {
    mat4 model;
    // The shadow draw's colour: rgb 0; alpha 1 (emulated) or the shadow factor (reference).
    vec4 colour;
    // The receiving plane (n, d): n.x + d = 0, n unit, pointing to the casters' side.
    vec4 plane;
    // x: the index in frame.lights of the light the shadow is cast from (the light's 64 bytes
    // stay in the frame's uniforms: they would pass the profile's limit here).
    uvec4 light;
} planar;
