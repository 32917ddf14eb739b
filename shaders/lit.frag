#version 450
// Opaque materials (no discard: early depth stays on).
#include "lit_shading.glsl"
