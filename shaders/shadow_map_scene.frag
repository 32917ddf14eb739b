#version 450
// Opaque materials (no discard: early depth stays on).
#include "shadow_map_scene_shading.glsl"
