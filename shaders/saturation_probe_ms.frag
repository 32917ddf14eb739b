#version 450
// The saturation probe of a multisampled frame: passes, for the occlusion query, only the
// samples whose alpha counter sits at its clamp once every volume is drawn, the samples the
// subpass apply counts with its atomic add.
layout(constant_id = 0) const int SAMPLES = 4;

layout(input_attachment_index = 0, set = 0, binding = 0) uniform subpassInputMS counter;

layout(location = 0) out vec4 out_colour;

void main() {
    int saturated = 0;
    for (int i = 0; i < SAMPLES; ++i) {
        if (subpassLoad(counter, i).a >= 1.0) {
            saturated |= 1 << i;
        }
    }
    if (saturated == 0) {
        discard;
    }
    gl_SampleMask[0] = saturated;
    out_colour = vec4(0.0);
}
