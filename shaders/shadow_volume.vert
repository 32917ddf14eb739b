#version 450
// Shadow-volume geometry in object space (Doom 3 BFG's doubled vertices): every vertex twice,
// w = 1 on the occluder and w = 0 to be pushed away from the light here (to infinity, or as far
// as the push's reach), so that a rigid caster's vertices are uploaded once and a frame writes
// only the indices the CPU chose. The infinite-far projection keeps w = 0 points in view.
// twin: skinned
#include "frame_uniforms.glsl"
#include "volume_push.glsl"
#include "volume_far_point.glsl"

layout(location = 0) in vec4 in_position;
#ifdef SKINNED
// A skinned caster's doubled bind pose (VertexLayout::SKINNED_POSITION4), skinned here as
// object_vertex.glsl skins the caster in the scene's passes, then extruded: Doom 3 BFG's
// shadow_skinned.vertex. The apex vertex has no weights: it starts at the push's centroid.
layout(location = 1) in uvec4 in_joints;
layout(location = 2) in vec4 in_weights;
#include "joint_palettes.glsl"
#endif

// How many counts each fragment adds (shadow_volume.frag): the multiplicity of the range
// drawn, passed as its draw's first instance, so that the volume's one push serves all its
// ranges (gl_InstanceIndex counts from firstInstance; each range is one instance).
layout(location = 0) flat out float weight;

// Invariant and written exactly as lit.vert writes it, so that caps on the occluder's own
// triangles land on the same depths as the occluder.
invariant gl_Position;

void main() {
    weight = float(gl_InstanceIndex);
#ifdef SKINNED
    vec4 posed = in_weights == vec4(0.0) ? vec4(object.apex.xyz, 1.0)
                                         : joint_palette_matrix(in_joints, in_weights) * vec4(in_position.xyz, 1.0);
    if (in_position.w != 0.0) {
        vec4 world = object.model * posed;
        gl_Position = frame.view_proj * world;
        return;
    }
    vec4 point = far_point(posed.xyz);
#else
    vec4 point = in_position.w == 0.0 ? far_point(in_position.xyz) : in_position;
#endif
    if (point.w == 0.0) {
        gl_Position = frame.view_proj * (object.model * vec4(point.xyz, 0.0));
    } else {
        vec4 world = object.model * vec4(point.xyz, 1.0);
        gl_Position = frame.view_proj * world;
    }
}
