#version 450
// Depth only, where the caster's material is not cut out.
#include "cut_out.glsl"

void main() {
    cut_out();
}
