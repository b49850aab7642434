#version 450 core
// The vertex colour, tinted where it is seen through the water.
in vec4 vColour;
in vec2 vWaterSides;
out vec4 oColour;
vec3 throughWater(vec3 colour, vec2 sides);  // water_view.frag
void main() { oColour = vec4(throughWater(vColour.rgb, vWaterSides), vColour.a); }
