#version 450
// Rectangle k = gl_VertexIndex / 6 of a 32 x 32 target, as two triangles: columns [4k, 4k + 4),
// rows [0, 4k + 4), edges on pixel boundaries, so the samples a draw passes are known by hand
// (16 (k + 1) a view). The fill-rate layer's test programs draw with it (tests/common/).
void main() {
    int k = gl_VertexIndex / 6;
    int corner = gl_VertexIndex % 6;
    // (0,0) (1,0) (0,1), (0,1) (1,0) (1,1)
    vec2 unit = vec2(corner == 1 || corner == 4 || corner == 5, corner == 2 || corner == 3 || corner == 5);
    vec2 pixel = vec2(4 * k, 0) + unit * vec2(4, 4 * k + 4);
    gl_Position = vec4(pixel / 16.0 - 1.0, 0.0, 1.0);
}
