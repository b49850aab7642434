#version 450 core
// Below the world height uLevel the water's colour, above it the node's: a node filled to its
// water level, whatever the body's heel (the water surface stays level); tinted where it is
// seen through the water outside.
in vec3 vWorld;
in vec3 vNormal;
in vec2 vWaterSides;
uniform vec3 uColour;
uniform vec3 uWater;
uniform float uLevel;
uniform vec3 uEye;
out vec4 oColour;
vec3 throughWater(vec3 colour, vec2 sides);  // water_view.frag
void main() {
    vec3 n = normalize(vNormal);
    float light = 0.45 + 0.55 * abs(dot(n, normalize(uEye - vWorld)));
    vec3 c = vWorld.y <= uLevel ? uWater : uColour;
    oColour = vec4(throughWater(c * light, vWaterSides), 1.0);
}
