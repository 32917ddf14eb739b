#version 450
// Shadow-volume geometry in object space (Doom 3 BFG's doubled vertices): every vertex twice,
// w = 1 on the occluder and w = 0 to be pushed away from the light here (to infinity, or as far
// as the push's reach), so that a rigid caster's vertices are uploaded once and a frame writes
// only the indices the CPU chose. The infinite-far projection keeps w = 0 points in view.
#include "frame_uniforms.glsl"
#include "volume_push.glsl"
#include "volume_far_point.glsl"

layout(location = 0) in vec4 in_position;

// Invariant and written exactly as lit.vert writes it, so that caps on the occluder's own
// triangles land on the same depths as the occluder.
invariant gl_Position;

void main() {
    vec4 point = in_position.w == 0.0 ? far_point(in_position.xyz) : in_position;
    if (point.w == 0.0) {
        gl_Position = frame.view_proj * (object.model * vec4(point.xyz, 0.0));
    } else {
        vec4 world = object.model * vec4(point.xyz, 1.0);
        gl_Position = frame.view_proj * world;
    }
}
