#version 450
// Geometry given directly in clip space (tests and screen-space overlays).
layout(location = 0) in vec4 in_clip;

void main() {
    gl_Position = in_clip;
}
