#version 450
// The multisampled subpass apply that also counts saturated samples (docs/design/saturation.md): alpha
// at 1.0 is the counter at its clamp, where increments may have been lost. One atomic add per
// pixel that has any, of the number of such samples.
#include "shadow_subpass_factor_ms.glsl"

layout(set = 0, binding = 1, std430) buffer Saturation {
    uint saturated_samples;
} saturation;

void main() {
    // Only the samples this invocation covers: lavapipe may shade a pixel once per sample
    // (each invocation then reads every sample of it), and a sample must be counted once.
    int saturated = saturated_samples() & gl_SampleMaskIn[0];
    if (saturated != 0) {
        atomicAdd(saturation.saturated_samples, uint(bitCount(saturated)));
    }
    write_factor(shadowed_samples());
}
