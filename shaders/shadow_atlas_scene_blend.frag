#version 450
// BLEND materials: the material's alpha goes out for the blend to use (colour only).
#define ALPHA_BLEND
#include "shadow_atlas_scene_shading.glsl"
