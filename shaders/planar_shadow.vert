#version 450
// twin: skinned
// The object's mesh flattened onto the receiving plane along the light.
#include "frame_uniforms.glsl"
#include "planar_push.glsl"
#include "planar_project.glsl"

#include "scene_vertex.glsl"
#include "object_vertex.glsl"

void main() {
    vec3 world = (planar.model * object_vertex().position).xyz;
    gl_Position = frame.view_proj * vec4(project_onto_plane(world, frame.lights[planar.light.x].position, planar.plane), 1.0);
}
