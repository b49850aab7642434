#version 450 core
// Flat shading from screen-space derivatives (no normals to upload), lit from the eye; the
// overlay texture (painted map, physics texture) over the uvs, or the base colour.
in vec3 vWorld;
in vec2 vUv;
uniform vec3 uEye;
uniform vec3 uViewDir;
uniform int uOrtho;
uniform int uHasOverlay;
uniform sampler2D uOverlay;
uniform vec2 uUvScale;
uniform vec2 uUvOffset;
uniform vec3 uBase;
uniform float uAlpha;
out vec4 oColour;
void main() {
    vec3 n = normalize(cross(dFdx(vWorld), dFdy(vWorld)));
    vec3 v = uOrtho != 0 ? -uViewDir : normalize(uEye - vWorld);
    float light = 0.35 + 0.65 * abs(dot(n, v));
    vec3 c = uHasOverlay != 0 ? texture(uOverlay, vUv * uUvScale + uUvOffset).rgb : uBase;
    oColour = vec4(c * light, uAlpha);
}
