#version 450
// Additive subpass mask, every sample of a multisampled frame (shadow_subpass_mask.glsl).
#define MULTISAMPLED
#include "shadow_subpass_mask.glsl"
