#version 450
// Dilation: a texel no triangle covered (alpha 0) takes the mean of the nearest covered texels
// within `radius` (Chebyshev rings), so filtering and mips near a chart border see the chart's
// own values, never the empty gutter or a neighbouring chart.
layout(set = 0, binding = 0) uniform sampler2D baked;

layout(push_constant) uniform Dilate {
    ivec4 params; // x: radius in texels
} dilate;

layout(location = 0) out vec4 out_texel;

void main() {
    ivec2 size = textureSize(baked, 0);
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 own = texelFetch(baked, p, 0);
    if (own.a > 0.5) {
        out_texel = vec4(own.rgb, 1.0);
        return;
    }
    for (int r = 1; r <= dilate.params.x; ++r) {
        vec4 sum = vec4(0.0);
        for (int dy = -r; dy <= r; ++dy) {
            for (int dx = -r; dx <= r; ++dx) {
                if (max(abs(dx), abs(dy)) != r) {
                    continue;
                }
                ivec2 q = p + ivec2(dx, dy);
                if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) {
                    continue;
                }
                vec4 t = texelFetch(baked, q, 0);
                if (t.a > 0.5) {
                    sum += vec4(t.rgb, 1.0);
                }
            }
        }
        if (sum.a > 0.0) {
            out_texel = vec4(sum.rgb / sum.a, 1.0);
            return;
        }
    }
    // Farther than the radius from every chart: never sampled; lit.
    out_texel = vec4(1.0, 1.0, 1.0, 0.0);
}
