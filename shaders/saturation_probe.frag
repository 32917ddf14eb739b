#version 450
// The opt-in saturation probe (`--saturation-probe`): passes, for the occlusion query, only
// where the alpha counter sits at its clamp once every volume is drawn, the pixels the subpass
// apply counts with its atomic add.
layout(input_attachment_index = 0, set = 0, binding = 0) uniform subpassInput counter;

layout(location = 0) out vec4 out_colour;

void main() {
    if (subpassLoad(counter).a < 1.0) {
        discard;
    }
    out_colour = vec4(0.0);
}
