// Per-draw values of the cartoon passes (112 of the profile's 128 push-constant bytes). The
// first 80 bytes have the layout of `object_push.glsl`.
layout(push_constant) uniform CartoonPush {
    mat4 model;
    // rgb: albedo or ink colour; a: the alpha this draw writes.
    vec4 colour;
    // cartoon_shade: x = 1 toon ramp (else Lambert), y = 1 dark-rim lookup of N.V, z = 1 flat
    // in colour.rgb (ink only).
    // cartoon_ink: x = line width in pixels, y = 1 one-sided (silhouette), z = clip-space depth pull.
    // cartoon_extrude: x = extrusion in pixels. outline_scale: x = scale, yzw = centre.
    // cartoon_alpha_test: x = the alpha reference (N.V at most this is ink).
    vec4 params;
    // xy: viewport size in pixels; z: world size of one pixel at unit distance from the eye.
    vec4 viewport;
} object;
