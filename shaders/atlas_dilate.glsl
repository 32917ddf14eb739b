// Dilation of a raw bake (shadow_atlas_dilate.frag, shadow_atlas_page.frag): a texel no
// triangle covered (alpha 0) takes the mean of the nearest covered texels within `radius`
// (Chebyshev rings) inside [lo, hi), so filtering and mips near a chart border see the chart's
// own values, never the empty gutter, a neighbouring chart or a neighbouring tile. Texels
// farther than the radius from every chart are never sampled: lit, alpha 0.
#ifndef ATLAS_DILATE_GLSL
#define ATLAS_DILATE_GLSL
vec4 dilated(sampler2D baked, ivec2 p, ivec2 lo, ivec2 hi, int radius) {
    vec4 own = texelFetch(baked, p, 0);
    if (own.a > 0.5) {
        return vec4(own.rgb, 1.0);
    }
    for (int r = 1; r <= radius; ++r) {
        vec4 sum = vec4(0.0);
        for (int dy = -r; dy <= r; ++dy) {
            for (int dx = -r; dx <= r; ++dx) {
                if (max(abs(dx), abs(dy)) != r) {
                    continue;
                }
                ivec2 q = p + ivec2(dx, dy);
                if (any(lessThan(q, lo)) || any(greaterThanEqual(q, hi))) {
                    continue;
                }
                vec4 t = texelFetch(baked, q, 0);
                if (t.a > 0.5) {
                    sum += vec4(t.rgb, 1.0);
                }
            }
        }
        if (sum.a > 0.0) {
            return vec4(sum.rgb / sum.a, 1.0);
        }
    }
    return vec4(1.0, 1.0, 1.0, 0.0);
}
#endif
