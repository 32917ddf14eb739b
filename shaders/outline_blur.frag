#version 450
// One 1D pass of the outline blur (seed 003's "Gaussian Blur" remark, as a box): the mean of
// channel R over 2r + 1 texels along `blur.xy`, r = `blur.z`. Texels outside the image count
// as 0, so the blur is the same whatever the sampler does at the edges.
layout(set = 0, binding = 0) uniform sampler2D source;

layout(push_constant) uniform BlurPush {
    // xy: direction (1, 0) or (0, 1); z: radius in texels.
    vec4 blur;
} push;

layout(location = 0) out vec4 out_value;

void main() {
    ivec2 here = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(source, 0);
    ivec2 step = ivec2(push.blur.xy);
    int radius = int(push.blur.z);
    float sum = 0.0;
    for (int i = -radius; i <= radius; ++i) {
        ivec2 p = here + i * step;
        if (all(greaterThanEqual(p, ivec2(0))) && all(lessThan(p, size))) {
            sum += texelFetch(source, p, 0).r;
        }
    }
    out_value = vec4(sum / float(2 * radius + 1), 0.0, 0.0, 1.0);
}
