#version 450
// As lit_light_subpass.frag, counting saturated pixels with fragment atomics.
#define READS_COUNT
#define COUNTED
#include "lit_light_shading.glsl"
