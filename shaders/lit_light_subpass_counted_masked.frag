#version 450
// As lit_light_subpass_counted.frag, on MASK and double-sided materials.
#define READS_COUNT
#define COUNTED
#define ALPHA_MASK
#include "lit_light_shading.glsl"
