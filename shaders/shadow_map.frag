#version 450
// Depth only: the shadow-map pass has no colour attachment.
void main() {
}
