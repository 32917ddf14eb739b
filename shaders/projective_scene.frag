#version 450
// Opaque materials (no discard: early depth stays on).
#define SHADOW_PROJECTIVE
#include "shadowed_scene_shading.glsl"
