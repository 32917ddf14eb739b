// Subpass normalisation of a multisampled frame (docs/design/msaa.md): one invocation per pixel
// reads the count of every sample from the multisampled colour (an input attachment of the same
// subpass) and writes the shadow's factors only to the shadowed samples, through gl_SampleMask.
// Lit samples keep their colour, as the reference's per-sample stencil test leaves them.
// `sampleRateShading` is not in the mobile profile, so the samples are read in a loop, not by
// one invocation each.
layout(constant_id = 0) const int SAMPLES = 4;

layout(input_attachment_index = 0, set = 0, binding = 0) uniform subpassInputMS counter;

layout(push_constant) uniform ShadowPush {
    // rgb: the shadow's factor per channel (D on each for a grey shadow, or a tint).
    vec4 shadow;
} push;

layout(location = 0) out vec4 out_colour;

// The samples with a count above 0 (shadowed), as a coverage mask.
int shadowed_samples() {
    int mask = 0;
    for (int i = 0; i < SAMPLES; ++i) {
        if (subpassLoad(counter, i).a > 0.0) {
            mask |= 1 << i;
        }
    }
    return mask;
}

// The samples whose counter sits at its clamp (alpha 1.0), as a coverage mask.
int saturated_samples() {
    int mask = 0;
    for (int i = 0; i < SAMPLES; ++i) {
        if (subpassLoad(counter, i).a >= 1.0) {
            mask |= 1 << i;
        }
    }
    return mask;
}

// Writes the factors to the samples in `shadowed`; a pixel with no shadowed sample is discarded.
void write_factor(int shadowed) {
    if (shadowed == 0) {
        discard;
    }
    gl_SampleMask[0] = shadowed;
    out_colour = vec4(push.shadow.rgb, 1.0);
}
