#version 450 core
// A body: world position, mesh uv and the light for the fragment shader. Each vertex carries
// its triangle's normal (the mesh is drawn flat, three vertices a triangle), and the light is
// worked out here, per vertex, not per pixel: on llvmpipe, forming the normal from
// screen-space derivatives in the fragment shader cost 2.5-3 ms of the buoy preview's 16 ms
// 3D view (1600 x 900).
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec2 aUv;
layout(location = 2) in vec3 aNormal;
uniform mat4 uModel;
uniform mat4 uViewProj;
uniform vec3 uEye;
uniform vec3 uViewDir;
uniform int uOrtho;
out vec2 vUv;
out float vLight;
out vec2 vWaterSides;
vec2 waterSides(vec3 world);  // water_view.vert
void main() {
    vec4 world = uModel * vec4(aPosition, 1.0);
    vec3 n = mat3(uModel) * aNormal;  // uModel: a rotation and a translation
    vec3 v = uOrtho != 0 ? -uViewDir : normalize(uEye - world.xyz);
    vLight = 0.35 + 0.65 * abs(dot(n, v));  // lit from the eye, both faces alike
    vUv = aUv;
    vWaterSides = waterSides(world.xyz);
    gl_Position = uViewProj * world;
}
