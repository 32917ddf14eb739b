#version 450
// Shadow-map pass, MASK casters: as shadow_map.vert, with the material's inputs.
// twin: skinned
#define LIGHT_SET 2
#include "shadow_atlas_light.glsl"
#include "light_push.glsl"
#include "atlas_vertex.glsl"
#include "object_vertex.glsl"
#include "material_out.glsl"

void main() {
    pass_material_inputs();
    gl_Position = shadow.lights[object.light.x].view_proj * (object.model * object_vertex().position);
}
