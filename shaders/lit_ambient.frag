#version 450
// The additive loop's ambient pass on opaque materials: ambient x albedo + emissive, no light
// (lit_shading.glsl with AMBIENT_ONLY).
#define AMBIENT_ONLY
#include "lit_shading.glsl"
