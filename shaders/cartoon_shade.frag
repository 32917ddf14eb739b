#version 450
// Opaque materials (no discard: early depth stays on).
#include "cartoon_shade_shading.glsl"
