#version 450
// The multisampled subpass apply on a device without fragment atomics: saturation is not
// counted.
#include "shadow_subpass_factor_ms.glsl"

void main() {
    write_factor(shadowed_samples());
}
