// Included by cartoon_shade.frag and its material variants (cartoon_shade_masked.frag: ALPHA_MASK,
// cartoon_shade_blend.frag: ALPHA_BLEND).
// Lambert, or N.L through a 1D ramp (toon), on the material's surface; optionally times the
// dark-rim texture at N.V.
#include "lights.glsl"
#include "cartoon_push.glsl"
#include "material.glsl"

// Nx1 textures, sampled on their middle row: the seed's "1D texture (or the first row of a 2D one)".
layout(set = 2, binding = 0) uniform sampler2D ramp;
layout(set = 2, binding = 1) uniform sampler2D rim;

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in float facing;
layout(location = 3) in vec2 uv0;
layout(location = 4) in vec2 uv1;
layout(location = 5) in vec4 vertex_colour;

layout(location = 0) out vec4 out_colour;

void main() {
    vec4 base = material_surface(uv0, uv1, vertex_colour);
    vec3 shade;
    if (object.params.z > 0.5) {
        // Ink only (the seed's figure 5.1.1, middle): faces in the push colour, the background.
        shade = object.colour.rgb;
    } else {
        vec3 n = surface_normal(world_normal);
        vec3 light;
        if (object.params.x > 0.5) {
            // Toon: the ramp at the primary light's N.L (a one-light stylisation).
            light = texture(ramp, vec2(frame_lambert(world_position, n), 0.5)).rgb;
        } else {
            light = all_lights(world_position, n);
        }
        shade = material_shade(base, light, uv0, uv1);
    }
    if (object.params.y > 0.5) {
        shade *= texture(rim, vec2(clamp(facing, 0.0, 1.0), 0.5)).rgb;
    }
    out_colour = vec4(shade, written_alpha(base));
}
