#version 450
// Shadow-volume geometry in object space: w = 1 vertices sit on the occluder, w = 0 vertices
// are directions extruded to infinity (the infinite-far projection keeps them in view).
#include "frame_uniforms.glsl"
#include "object_push.glsl"

layout(location = 0) in vec4 in_position;

// Invariant and written exactly as lit.vert writes it, so that caps on the occluder's own
// triangles land on the same depths as the occluder.
invariant gl_Position;

void main() {
    if (in_position.w == 0.0) {
        gl_Position = frame.view_proj * (object.model * vec4(in_position.xyz, 0.0));
    } else {
        vec4 world = object.model * vec4(in_position.xyz, 1.0);
        gl_Position = frame.view_proj * world;
    }
}
