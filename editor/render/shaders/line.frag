#version 450 core
// The vertex colour, tinted where it is seen through the water.
in vec4 vColour;
in vec3 vWorld;
out vec4 oColour;
vec3 throughWater(vec3 colour, vec3 world);  // water_view.frag
void main() { oColour = vec4(throughWater(vColour.rgb, vWorld), vColour.a); }
