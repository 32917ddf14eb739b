#version 450
// The atlas page pass, one fragment per texel of each tile re-baked:
// - a geometry image's tile is baked by its texels: the surface point the texel holds
//   (texel_surface.rs) is tested against the maps of the lights the bake holds, as the
//   rasterised bake's fragment is (shadow_atlas_bake.frag);
// - a rasterised tile is dilated from the raw bake, within its own tile (atlas_dilate.glsl).
// Branches here are on flat inputs and push constants, never on a uniform buffer (see
// toward_light.glsl for why).
#define LIGHT_SET 0
#include "shadow_atlas_light.glsl"
#include "atlas_page_tiles.glsl"
#include "atlas_dilate.glsl"

layout(set = 2, binding = 0) uniform sampler2D raw_bake;

layout(push_constant) uniform Page {
    // xy: the page's size in texels; z: the baked channels (lights with a map, at most 3).
    vec4 size;
} page;

layout(location = 0) flat in ivec4 rect;
layout(location = 1) flat in int radius;
layout(location = 2) flat in mat4 model;
layout(location = 6) flat in mat3 normal_matrix;

layout(location = 0) out vec4 out_texel;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (rect.w < 0) {
        out_texel = dilated(raw_bake, p, rect.xy, rect.xy + rect.z, radius);
        return;
    }
    ivec2 local = p - rect.xy;
    int texel = rect.w + 2 * (local.y * rect.z + local.x);
    vec3 world_position = (model * surface[texel]).xyz;
    vec3 world_normal = normal_matrix * surface[texel + 1].xyz;
    // Channel c holds the light in map layer c (maps.rs), so the baked channels come first.
    vec3 visible = vec3(1.0);
    int channels = int(page.size.z);
    for (int c = 0; c < channels; ++c) {
        visible[c] = shadow_visibility(shadow.channels[c], world_position, world_normal);
    }
    out_texel = vec4(visible, 1.0);
}
