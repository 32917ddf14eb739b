#version 450
// twin: skinned
// A MASK caster flattened onto the receiving plane (planar_shadow.vert), with the material's
// inputs for the cut-out.
#include "frame_uniforms.glsl"
#include "planar_push.glsl"
#include "planar_project.glsl"
#include "scene_vertex.glsl"
#include "object_vertex.glsl"
#include "material_out.glsl"

void main() {
    pass_material_inputs();
    vec3 world = (planar.model * object_vertex().position).xyz;
    gl_Position = frame.view_proj * vec4(project_onto_plane(world, frame.lights[planar.light.x].position, planar.plane), 1.0);
}
