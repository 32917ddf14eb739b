#version 450
// Opaque materials (no discard: early depth stays on).
#include "shadowed_scene_shading.glsl"
