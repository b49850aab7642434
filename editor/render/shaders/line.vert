#version 450 core
// Lines and the water surface: a colour per vertex.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec4 aColour;
uniform mat4 uViewProj;
out vec4 vColour;
void main() { vColour = aColour; gl_Position = uViewProj * vec4(aPosition, 1.0); }
