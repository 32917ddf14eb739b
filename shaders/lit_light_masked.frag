#version 450
// One light of the additive loop on MASK and double-sided materials: texels below the cutoff
// are discarded, as the ambient pass discarded them.
#define ALPHA_MASK
#include "lit_light_shading.glsl"
