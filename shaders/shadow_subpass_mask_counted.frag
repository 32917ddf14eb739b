#version 450
// Additive subpass mask, one sample, counting saturated pixels with fragment atomics
// (shadow_subpass_mask.glsl).
#define COUNTED
#include "shadow_subpass_mask.glsl"
