#version 450
// Shadow-map pass of one light (the push's light index): casters seen from it, depth only,
// into the light's layer of the map array.
#define LIGHT_SET 0
#include "shadow_atlas_light.glsl"
#include "light_push.glsl"

#include "atlas_vertex.glsl"

void main() {
    gl_Position = shadow.lights[object.light.x].view_proj * (object.model * vec4(in_position, 1.0));
}
