#version 450
// Shadow-map pass of one light (the push's light index): casters seen from it, depth only,
// into the light's layer of the map array. Sets: the frame's (its joint palettes), the
// material, the lights.
// twin: skinned
#define LIGHT_SET 2
#include "shadow_atlas_light.glsl"
#include "light_push.glsl"

#include "atlas_vertex.glsl"
#include "object_vertex.glsl"

void main() {
    gl_Position = shadow.lights[object.light.x].view_proj * (object.model * object_vertex().position);
}
