#version 450 core
// The vertex colour as it is (lines, water).
in vec4 vColour;
out vec4 oColour;
void main() { oColour = vColour; }
