// Additive mode's `subpass` normalisation, one light at a time: read the light's volume count,
// held as a down-counter (alpha 1 is a count of 0, each count takes k/255 off), and write alpha
// 0 where it is not 1, so that the light's shading pass, weighted by the destination alpha, adds
// nothing there. Lit pixels (and, multisampled, lit samples) are left at 1. No blend: alpha is
// written, colour masked off.
layout(location = 0) out vec4 out_colour;

#ifdef MULTISAMPLED
// `sampleRateShading` is not in the mobile profile: one invocation reads every sample.
layout(constant_id = 0) const int SAMPLES = 4;
layout(input_attachment_index = 0, set = 0, binding = 0) uniform subpassInputMS counter;

// The samples whose alpha is below 1 (shadowed) and at 0 (saturated), as coverage masks: each
// sample read once.
ivec2 shadowed_and_saturated() {
    ivec2 masks = ivec2(0);
    for (int i = 0; i < SAMPLES; ++i) {
        float a = subpassLoad(counter, i).a;
        masks.x |= a < 1.0 ? 1 << i : 0;
        masks.y |= a < 1.0 / 512.0 ? 1 << i : 0;
    }
    return masks;
}
#else
layout(input_attachment_index = 0, set = 0, binding = 0) uniform subpassInput counter;
#endif

#ifdef COUNTED
// Samples whose counter sits at its clamp (alpha 0: a count of 255/k or more), counted once.
layout(set = 0, binding = 1, std430) buffer Saturation {
    uint saturated_samples;
} saturation;
#endif

void main() {
#ifdef MULTISAMPLED
    ivec2 masks = shadowed_and_saturated();
    int shadowed = masks.x;
#ifdef COUNTED
    // Only the samples this invocation covers (lavapipe may shade a pixel once per sample).
    int saturated = masks.y & gl_SampleMaskIn[0];
    if (saturated != 0) {
        atomicAdd(saturation.saturated_samples, uint(bitCount(saturated)));
    }
#endif
    if (shadowed == 0) {
        discard;
    }
    gl_SampleMask[0] = shadowed;
#else
    float count = subpassLoad(counter).a;
#ifdef COUNTED
    if (count <= 0.0) {
        atomicAdd(saturation.saturated_samples, 1u);
    }
#endif
    if (count >= 1.0) {
        discard;
    }
#endif
    out_colour = vec4(0.0);
}
