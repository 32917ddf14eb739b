#version 450
// The atlas page pass over a geometry image's tile, one fragment per texel: the surface point
// the texel holds (texel_surface.rs) is tested against the maps of the lights the bake holds,
// as the rasterised bake's fragment is (shadow_atlas_bake.frag). Rasterised tiles are dilated
// by their own pipeline (shadow_atlas_page_dilate.frag): on a software rasteriser a branch
// between the two runs both sides for every texel.
#define LIGHT_SET 0
#include "shadow_atlas_light.glsl"
#include "atlas_page_tiles.glsl"

layout(push_constant) uniform Page {
    // xy: the page's size in texels; z: the baked channels (lights with a map, at most 3).
    vec4 size;
} page;

layout(location = 0) flat in ivec4 rect;
layout(location = 2) flat in mat4 model;
layout(location = 6) flat in mat3 normal_matrix;

layout(location = 0) out vec4 out_texel;

void main() {
    ivec2 local = ivec2(gl_FragCoord.xy) - rect.xy;
    uvec4 texel = surface[rect.w + local.y * rect.z + local.x];
    vec3 world_position = (model * vec4(texel_position(texel), 1.0)).xyz;
    vec3 world_normal = normal_matrix * texel_normal(texel);
    // Channel c holds the light in map layer c (maps.rs), so the baked channels come first.
    vec3 visible = vec3(1.0);
    int channels = int(page.size.z);
    for (int c = 0; c < channels; ++c) {
        visible[c] = shadow_visibility(shadow.channels[c], world_position, world_normal);
    }
    out_texel = vec4(visible, 1.0);
}
