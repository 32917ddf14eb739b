// A scene object's vertex in the object's space, after the vertex inputs (scene_vertex.glsl or
// atlas_vertex.glsl: in_position, in_normal, and SKIN_LOCATION, the first location they leave
// free). Compiled plain, it is the mesh's vertex as stored; in a shader's skinned twin (SKINNED
// defined, see build.rs) it is the bind pose skinned by the frame's joint palettes, JOINTS_0 and
// WEIGHTS_0 following the layout's attributes (VertexLayout::skinned). Every stage that draws
// scene objects reads its vertex here, so rigid and skinned objects go through one source.
#ifdef SKINNED
layout(location = SKIN_LOCATION) in uvec4 in_joints;
layout(location = SKIN_LOCATION + 1) in vec4 in_weights;
#include "joint_palettes.glsl"
#endif

struct ObjectVertex {
    vec4 position;
    vec3 normal;
};

ObjectVertex object_vertex() {
#ifdef SKINNED
    mat4 skin = joint_palette_matrix(in_joints, in_weights);
    // Normals by the inverse transpose, right under non-uniform scale (as on the CPU).
    return ObjectVertex(skin * vec4(in_position, 1.0), transpose(inverse(mat3(skin))) * in_normal);
#else
    return ObjectVertex(vec4(in_position, 1.0), in_normal);
#endif
}
