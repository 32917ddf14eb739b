#version 450
// The additive loop's ambient pass on MASK and double-sided materials.
#define AMBIENT_ONLY
#define ALPHA_MASK
#include "lit_shading.glsl"
