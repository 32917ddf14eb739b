// Subpass normalisation: read this pixel's volume count from the colour attachment (an input
// attachment of the same subpass) and output the shadow's factors as colour; the blend unit does
// the multiply (ZERO, SRC_COLOR), exactly as the stencil-tested reference apply pass does.
layout(input_attachment_index = 0, set = 0, binding = 0) uniform subpassInput counter;

layout(push_constant) uniform ShadowPush {
    // rgb: the shadow's factor per channel (D on each for a grey shadow, or a tint).
    vec4 shadow;
} push;

layout(location = 0) out vec4 out_colour;

// A lit pixel (count 0) is discarded: left untouched, as the reference's stencil test leaves it.
vec4 shadow_factor(float count) {
    if (count <= 0.0) {
        discard;
    }
    return vec4(push.shadow.rgb, 1.0);
}
