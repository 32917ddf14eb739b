#version 450
// One light of the additive loop at one sample with the `subpass` normalisation: the count read
// here, no mask pass (lit_light_shading.glsl).
#define READS_COUNT
#include "lit_light_shading.glsl"
