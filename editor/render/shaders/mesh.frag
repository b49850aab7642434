#version 450 core
// Flat shading lit from the eye (the light comes from the vertex shader); the overlay texture
// (painted map, physics texture) over the uvs, or the base colour; tinted where it is seen
// through the water.
in vec2 vUv;
in float vLight;
in vec2 vWaterSides;
uniform int uHasOverlay;
uniform sampler2D uOverlay;
uniform vec2 uUvScale;
uniform vec2 uUvOffset;
uniform vec3 uBase;
uniform float uAlpha;
out vec4 oColour;
vec3 throughWater(vec3 colour, vec2 sides);  // water_view.frag
void main() {
    vec3 c = uHasOverlay != 0 ? texture(uOverlay, vUv * uUvScale + uUvOffset).rgb : uBase;
    oColour = vec4(throughWater(c * vLight, vWaterSides), uAlpha);
}
