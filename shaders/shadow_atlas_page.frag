#version 450
// The atlas page pass over a geometry image's tile, one fragment per texel: the surface point
// the texel holds (texel_surface.rs) is tested against the maps of the lights the bake holds,
// as the rasterised bake's fragment is (shadow_atlas_bake.frag). Rasterised tiles are dilated
// by their own pipeline (shadow_atlas_page_dilate.frag): on a software rasteriser a branch
// between the two runs both sides for every texel.
#define LIGHT_SET 0
#include "shadow_atlas_light.glsl"
#include "atlas_page_tiles.glsl"

// The scene's lights (specialization constant 1, as in lights.glsl): the loop below unrolls,
// so every light's uniforms are read at constant offsets. Indexed by a value read from a
// uniform (the channel's light), they would be a gather per lane on a software rasteriser,
// which made the bake half again as slow.
layout(constant_id = 1) const int LIGHT_COUNT = 1;

layout(location = 0) flat in ivec4 rect;
layout(location = 2) flat in mat4 model;
layout(location = 6) flat in mat3 normal_matrix;

layout(location = 0) out vec4 out_texel;

void main() {
    ivec2 local = ivec2(gl_FragCoord.xy) - rect.xy;
    uvec4 texel = surface[rect.w + local.y * rect.z + local.x];
    vec3 world_position = (model * vec4(texel_position(texel), 1.0)).xyz;
    vec3 world_normal = normal_matrix * texel_normal(texel);
    // Channel c holds the light in map layer c (maps.rs); a light with no channel is not
    // baked (its visibility is computed all the same: selects, no branch on a uniform).
    vec3 visible = vec3(1.0);
    for (int i = 0; i < LIGHT_COUNT; ++i) {
        float v = shadow_visibility(i, world_position, world_normal);
        for (int c = 0; c < 3; ++c) {
            visible[c] = shadow.channels[c] == i ? v : visible[c];
        }
    }
    out_texel = vec4(visible, 1.0);
}
