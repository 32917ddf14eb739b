// A model's shadow texture, read from its tile of the atlas page (shadow_atlas::page). A texture
// of its own was sampled trilinearly with CLAMP_TO_EDGE and its own mip count; in the page:
// - the tile's set binds a view of the page with the tile's mip count, so the hardware's LOD
//   stops at the tile's last clean mip;
// - the UV is kept half a texel of the coarser level read inside the tile, so neither level's
//   bilinear footprint reaches a neighbouring tile (at the finer level it then stops up to half
//   a texel short of the border, where CLAMP_TO_EDGE would have repeated the border texel);
// - the gradients are the unclamped UV's, so the LOD is the one the texture had everywhere.
// One hardware read, as before: the LOD is computed in the shader only to place the clamp.
layout(set = 2, binding = 0) uniform sampler2D shadow_page;
layout(set = 2, binding = 1) uniform AtlasTile {
    // xy: the tile's corner, zw: its side, in page UV.
    vec4 rect;
    // x: its last mip; y: its side in texels of mip 0.
    vec4 mips;
} atlas_tile;

vec4 sample_tile(vec2 uv) {
    vec2 dx = dFdx(uv);
    vec2 dy = dFdy(uv);
    float footprint = max(length(dx), length(dy)) * atlas_tile.mips.y;
    float coarser = ceil(clamp(log2(footprint), 0.0, atlas_tile.mips.x));
    float half_texel = 0.5 * exp2(coarser) / atlas_tile.mips.y;
    vec2 inside = clamp(uv, vec2(half_texel), vec2(1.0 - half_texel));
    vec2 scale = atlas_tile.rect.zw;
    return textureGrad(shadow_page, atlas_tile.rect.xy + inside * scale, dx * scale, dy * scale);
}
