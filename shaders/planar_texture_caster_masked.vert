#version 450
// twin: skinned
// Shadow texture: a MASK caster drawn from the light (planar_texture_caster.vert), with the
// material's inputs for the cut-out.
#include "object_push.glsl"
#include "scene_vertex.glsl"
#include "object_vertex.glsl"
#include "material_out.glsl"

void main() {
    pass_material_inputs();
    gl_Position = object.model * object_vertex().position;
}
