#version 450
// The blurred outline over the frame: coverage = blurred mask x (1 - selected), where the mask
// target's alpha marks the selected objects (so the blur never covers them), blended over the
// frame in the outline colour (SRC_ALPHA, ONE_MINUS_SRC_ALPHA, write mask RGB).
layout(set = 0, binding = 0) uniform sampler2D blurred;
layout(set = 0, binding = 1) uniform sampler2D mask;

layout(push_constant) uniform ApplyPush {
    // rgb: the outline colour (linear).
    vec4 colour;
} push;

layout(location = 0) out vec4 out_colour;

void main() {
    ivec2 here = ivec2(gl_FragCoord.xy);
    float cover = texelFetch(blurred, here, 0).r * (1.0 - texelFetch(mask, here, 0).a);
    out_colour = vec4(push.colour.rgb, cover);
}
