// The frame's joint palettes (set 0, binding 1): every skinned object's joint matrices, one
// palette after another (scene::JointPalettes); a skinned vertex's JOINTS_0 were moved up by
// its object's first joint when it was uploaded. Linear blend skinning as
// scene::skinning::skin_positions_normals does it on the CPU (weights sum to 1: the loader
// renormalises them).
layout(std430, set = 0, binding = 1) readonly buffer JointPalettes {
    mat4 joints[];
} palettes;

mat4 joint_palette_matrix(uvec4 joints, vec4 weights) {
    // A bad index stays inside the buffer.
    uvec4 j = min(joints, uvec4(uint(palettes.joints.length()) - 1u));
    return palettes.joints[j.x] * weights.x + palettes.joints[j.y] * weights.y + palettes.joints[j.z] * weights.z +
           palettes.joints[j.w] * weights.w;
}
