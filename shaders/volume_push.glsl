// Per-draw values of a volume extruded on the GPU (all of the profile's 128 push-constant bytes;
// technique::shadow_volume::gpu_extrusion::VolumePush). The first 80 are ObjectPush's.
layout(push_constant) uniform VolumePush {
    mat4 model;
    // a: the alpha one count adds (k / 255).
    vec4 colour;
    // The light in the caster's own space: xyz its position (w = 1) or the direction it
    // travels (w = 0).
    vec4 light;
    // xyz: a GPU-skinned caster's centroid in this frame's pose, where its apex vertex (the
    // bounded far cap's, which has no weights) starts.
    vec4 apex;
    // The caster's first word in the shadow-mesh tables.
    uint mesh;
    // Bit 0: draw each wall |m| times as instances, each counting 1 (the stencil), instead of
    // once counting |m| (the alpha counter); bits 1-2: the far end (0 infinity, 1 `reach`
    // along a directional light, 2 `reach` times as far from a point light).
    uint flags;
    float reach;
    uint unused;
} object;
