// GPU linear blend skinning (set PALETTE_SET, 1 unless defined, binding 0): 256 joint matrices = 16 KiB, the mobile profile's
// maxUniformBufferRange (scene::MAX_JOINTS). Mirrors scene::skinning::skin_positions_normals, the CPU oracle.
#ifndef PALETTE_SET
#define PALETTE_SET 1
#endif
layout(set = PALETTE_SET, binding = 0) uniform JointPalette {
    mat4 joints[256];
} palette;

mat4 skin_matrix(uvec4 joints, vec4 weights) {
    // The loader keeps indices inside the skin; the clamp keeps a bad index inside the buffer.
    uvec4 j = min(joints, uvec4(255u));
    return palette.joints[j.x] * weights.x + palette.joints[j.y] * weights.y + palette.joints[j.z] * weights.z +
           palette.joints[j.w] * weights.w;
}
