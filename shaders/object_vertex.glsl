// A scene object's vertex in the object's space. Compiled plain, it is the mesh's vertex as
// stored (VertexLayout::SCENE); in a shader's skinned twin (SKINNED defined, see build.rs) it is
// the bind pose skinned by the frame's joint palettes (VertexLayout::SKINNED_SCENE). Every
// stage that draws scene objects reads its vertex here, so rigid and skinned objects go through
// one shader source.
#include "scene_vertex.glsl"
#ifdef SKINNED
layout(location = 5) in uvec4 in_joints;
layout(location = 6) in vec4 in_weights;
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
