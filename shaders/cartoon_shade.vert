#version 450
// Scene geometry for the cartoon techniques: world position and normal, and N.V per vertex
// (seed 002's vertex-shader silhouette: the texture coordinate of the dark-rim lookup).
// twin: skinned
#include "frame_uniforms.glsl"
#include "cartoon_push.glsl"

invariant gl_Position;

#include "scene_vertex.glsl"
#include "object_vertex.glsl"

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out float facing;
layout(location = 3) out vec2 uv0;
layout(location = 4) out vec2 uv1;
layout(location = 5) out vec4 vertex_colour;

void main() {
    ObjectVertex vertex = object_vertex();
    vec4 world = object.model * vertex.position;
    world_position = world.xyz;
    world_normal = transpose(inverse(mat3(object.model))) * vertex.normal;
    vec3 to_eye = normalize(frame.camera_position.xyz - world.xyz);
    facing = dot(normalize(world_normal), to_eye);
    uv0 = in_uv0;
    uv1 = in_uv1;
    vertex_colour = in_colour;
    gl_Position = frame.view_proj * world;
}
