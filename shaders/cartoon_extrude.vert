#version 450
// A copy of the mesh pushed out along its smooth (welded) normals by about `params.x` pixels:
// the distance grows with the distance to the eye, so the rim keeps its width on screen.
// Used for the seed-003 outline copy and the seed-002 inverted hull.
#include "frame_uniforms.glsl"
#include "cartoon_push.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

void main() {
    vec4 world = object.model * vec4(in_position, 1.0);
    vec3 n = normalize(transpose(inverse(mat3(object.model))) * in_normal);
    float distance_to_eye = length(world.xyz - frame.camera_position.xyz);
    world.xyz += n * (object.params.x * object.viewport.z * distance_to_eye);
    gl_Position = frame.view_proj * world;
}
