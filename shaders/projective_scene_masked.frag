#version 450
// MASK materials, and double-sided ones: texels below the cutoff are discarded.
#define ALPHA_MASK
#define SHADOW_PROJECTIVE
#include "shadowed_scene_shading.glsl"
