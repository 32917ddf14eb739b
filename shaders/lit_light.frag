#version 450
// One light of the additive loop on opaque materials (lit_light_shading.glsl).
#include "lit_light_shading.glsl"
