#version 450
// A copy of the mesh scaled up about its centre (seed 003, the document's outline): params.x is
// the scale, params.yzw the centre in the mesh's own coordinates. The normal is declared, not
// used: the copy shares the extruded copy's vertex buffer.
#include "frame_uniforms.glsl"
#include "cartoon_push.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

void main() {
    vec3 centre = object.params.yzw;
    vec3 scaled = centre + object.params.x * (in_position - centre);
    gl_Position = frame.view_proj * object.model * vec4(scaled, 1.0);
}
