// What a shadow caster's vertex shader hands a cut-out test (`cut_out.glsl`): its UV sets and
// COLOR_0, as read from the vertex.
layout(location = 0) out vec2 uv0;
layout(location = 1) out vec2 uv1;
layout(location = 2) out vec4 vertex_colour;

void pass_material_inputs() {
    uv0 = in_uv0;
    uv1 = in_uv1;
    vertex_colour = in_colour;
}
