#version 450
// Additive subpass mask, every sample, counting saturated samples with fragment atomics
// (shadow_subpass_mask.glsl).
#define MULTISAMPLED
#define COUNTED
#include "shadow_subpass_mask.glsl"
