// What lit.vert hands the fragment shaders of the lit scene passes (lit_shading.glsl,
// lit_light_shading.glsl), and their one colour output.
layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in vec2 uv0;
layout(location = 3) in vec2 uv1;
layout(location = 4) in vec4 vertex_colour;

layout(location = 0) out vec4 out_colour;
