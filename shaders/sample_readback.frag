#version 450
// The per-sample read-back (tests only): pixel (x * N + i, y) of a one-sample image receives
// sample i of pixel (x, y) of the kept multisampled frame. The target has the frame's format,
// so an sRGB colour decoded by the fetch is encoded again on write and alpha stays linear.
layout(set = 0, binding = 0) uniform sampler2DMS frame;

layout(push_constant) uniform ReadbackPush {
    int samples;
} push;

layout(location = 0) out vec4 out_colour;

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    out_colour = texelFetch(frame, ivec2(texel.x / push.samples, texel.y), texel.x % push.samples);
}
