#version 450
// The one-sample subpass apply that also counts saturated samples, here pixels
// (docs/design/saturation.md): alpha at 1.0 is the counter at its clamp, a count of 255/k or more, where
// increments may have been lost. One atomic add per such pixel, in the pass the frame draws
// anyway.
#include "shadow_subpass_factor.glsl"

layout(set = 0, binding = 1, std430) buffer Saturation {
    uint saturated_samples;
} saturation;

void main() {
    float count = subpassLoad(counter).a;
    if (count >= 1.0) {
        atomicAdd(saturation.saturated_samples, 1u);
    }
    out_colour = shadow_factor(count);
}
