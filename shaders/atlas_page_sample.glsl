// A model's shadow texture, read from its tile of the atlas page (shadow_atlas::page). A texture
// of its own was sampled trilinearly with CLAMP_TO_EDGE and its own mip count; in the page:
// - the tile's set binds a view of the page with the tile's mip count, so the hardware's LOD
//   stops at the tile's last clean mip;
// - the UV is kept at least half a texel of the coarser level read inside the tile, so neither
//   level's bilinear footprint reaches a neighbouring tile (at the finer level it then stops up
//   to a texel short of the border, where CLAMP_TO_EDGE would have repeated the border texel);
// - the LOD is the hardware's own, from the page UV's derivatives (page UV = tile UV scaled by
//   tile / page, so the LOD equals the tile texture's), but in the clamped outermost ring, where
//   the clamp flattens one derivative and the LOD drops by up to one level (`textureGrad` with
//   the unclamped gradients would keep it, at the cost of a LOD per pixel on lavapipe: 15%
//   slower frames).
// One hardware read, as before: the footprint is estimated in the shader only to place the clamp.
layout(set = 2, binding = 0) uniform sampler2D shadow_page;
layout(set = 2, binding = 1) uniform AtlasTile {
    // xy: the tile's corner, zw: its side, in page UV.
    vec4 rect;
    // x: its last mip; y: its side in texels of mip 0; z: half a texel of its last mip, in
    // texels of mip 0 (2^x / 2).
    vec4 mips;
} atlas_tile;

vec4 sample_tile(vec2 uv) {
    // The footprint in texels of mip 0: between 2^L and 2^(L+1) the levels read are L and L + 1,
    // whose half texel is 2^L: the footprint itself is at least that (at least half a texel of
    // mip 0, at most half a texel of the last mip), with no log2 per pixel. A fifth more covers
    // the hardware's own LOD rounding (a fast log2 may read a level up early).
    vec2 dx = dFdx(uv);
    vec2 dy = dFdy(uv);
    float footprint = 1.2 * sqrt(max(dot(dx, dx), dot(dy, dy))) * atlas_tile.mips.y;
    float margin = clamp(footprint, 0.5, atlas_tile.mips.z) / atlas_tile.mips.y;
    vec2 inside = clamp(uv, vec2(margin), vec2(1.0 - margin));
    return texture(shadow_page, atlas_tile.rect.xy + inside * atlas_tile.rect.zw);
}
