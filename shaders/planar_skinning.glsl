// GPU linear blend skinning (set 1, binding 0): 64 joint matrices = 4 KiB, the mobile profile's
// palette (scene::MAX_JOINTS). Mirrors scene::skinning::skin_positions_normals, the CPU oracle.
layout(set = 1, binding = 0) uniform JointPalette {
    mat4 joints[64];
} palette;

mat4 skin_matrix(uvec4 joints, vec4 weights) {
    // The loader keeps indices inside the skin; the clamp keeps a bad index inside the buffer.
    uvec4 j = min(joints, uvec4(63u));
    return palette.joints[j.x] * weights.x + palette.joints[j.y] * weights.y + palette.joints[j.z] * weights.z +
           palette.joints[j.w] * weights.w;
}
