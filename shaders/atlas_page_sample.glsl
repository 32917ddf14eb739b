// A model's shadow texture, read from its tile of the atlas page (shadow_atlas::page). The
// hardware's trilinear filter would read across the tile's border (the page has neighbours
// where a texture of its own had CLAMP_TO_EDGE) and past the tile's last clean mip, so the
// levels are read by hand: the LOD as the hardware computes it (the larger footprint's log2),
// clamped to the tile's mips, and each level's bilinear read kept half a texel inside the tile,
// which is what CLAMP_TO_EDGE reads. A magnified tile (the common case up close) is one read.
layout(set = 2, binding = 0) uniform sampler2D shadow_page;
layout(set = 2, binding = 1) uniform AtlasTile {
    // xy: the tile's corner, zw: its side, in page UV.
    vec4 rect;
    // x: its last mip (a level past it would mix in gutters or neighbours); y: its side in
    // texels of mip 0.
    vec4 mips;
} atlas_tile;

vec4 tile_level(vec2 uv, float level) {
    float texels = atlas_tile.mips.y / exp2(level);
    vec2 inside = clamp(uv, vec2(0.5 / texels), vec2(1.0 - 0.5 / texels));
    return textureLod(shadow_page, atlas_tile.rect.xy + inside * atlas_tile.rect.zw, level);
}

vec4 sample_tile(vec2 uv) {
    vec2 texel = uv * atlas_tile.mips.y;
    float rho = max(length(dFdx(texel)), length(dFdy(texel)));
    float lod = clamp(log2(rho), 0.0, atlas_tile.mips.x);
    float base = floor(lod);
    vec4 fine = tile_level(uv, base);
    float blend = lod - base;
    if (blend > 0.0) {
        fine = mix(fine, tile_level(uv, base + 1.0), blend);
    }
    return fine;
}
