#version 450
// Shadow-map pass: casters seen from the light, depth only.
#define LIGHT_SET 0
#include "shadow_atlas_light.glsl"
#include "object_push.glsl"

#include "atlas_vertex.glsl"

void main() {
    gl_Position = shadow.view_proj * (object.model * vec4(in_position, 1.0));
}
