#version 450
// Looks the receiver's pixel up in the shadow texture (1 lit, the shadow factor where a caster
// was drawn) and outputs it as the factor the pixel is multiplied by (blend ZERO, SRC_COLOR).
// Outside the texture, or behind a point light, nothing is shadowed.
layout(set = 1, binding = 0) uniform sampler2D shadow_texture;

layout(location = 0) in vec4 light_clip;

layout(location = 0) out vec4 out_factor;

void main() {
    float factor = 1.0;
    if (light_clip.w > 0.0) {
        vec2 uv = light_clip.xy / light_clip.w * 0.5 + 0.5;
        if (all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)))) {
            factor = texture(shadow_texture, uv).r;
        }
    }
    out_factor = vec4(vec3(factor), 1.0);
}
