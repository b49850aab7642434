#version 450 core
// Lines (grid, axes, the UV wireframe): a colour per vertex.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec4 aColour;
uniform mat4 uViewProj;
out vec4 vColour;
out vec2 vWaterSides;
vec2 waterSides(vec3 world);  // water_view.vert
void main() {
    vColour = aColour;
    vWaterSides = waterSides(aPosition);
    gl_Position = uViewProj * vec4(aPosition, 1.0);
}
