#version 450
// Passes (for the occlusion query) only where the alpha counter sits at its ceiling: the
// pixels whose count reached 255 after every increment, where further increments were lost.
layout(input_attachment_index = 0, set = 0, binding = 0) uniform subpassInput counter;

layout(location = 0) out vec4 out_colour;

void main() {
    if (subpassLoad(counter).a < 1.0) {
        discard;
    }
    out_colour = vec4(0.0);
}
