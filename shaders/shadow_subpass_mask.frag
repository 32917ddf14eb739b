#version 450
// Additive subpass mask, one sample (shadow_subpass_mask.glsl).
#include "shadow_subpass_mask.glsl"
