#version 450
// A compute stage for the fill-rate layer's tests (tests/common/work_program.rs): every
// invocation adds `value` to its own word of a width-wide grid, so the program can check what it
// computed, and knows its invocation count exactly (8 x 4 per workgroup).

layout(local_size_x = 8, local_size_y = 4, local_size_z = 1) in;

layout(std430, set = 0, binding = 0) buffer Words {
    uint words[];
};

layout(push_constant) uniform Push {
    uint width;
    uint value;
};

void main() {
    uvec3 id = gl_GlobalInvocationID;
    words[id.y * width + id.x] += value;
}
