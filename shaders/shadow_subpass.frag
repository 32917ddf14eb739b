#version 450
// The subpass apply on a device without fragment atomics: saturation is not counted.
#include "shadow_subpass_factor.glsl"

void main() {
    out_colour = shadow_factor(subpassLoad(counter).a);
}
