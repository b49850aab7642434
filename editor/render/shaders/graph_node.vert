#version 450 core
// A water-graph node (sphere or box) placed by uModel, with its normals.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
uniform mat4 uModel;
uniform mat4 uViewProj;
out vec3 vWorld;
out vec3 vNormal;
out vec2 vWaterSides;
vec2 waterSides(vec3 world);  // water_view.vert
void main() {
    vec4 world = uModel * vec4(aPosition, 1.0);
    vWorld = world.xyz;
    vWaterSides = waterSides(world.xyz);
    vNormal = mat3(transpose(inverse(uModel))) * aNormal;
    gl_Position = uViewProj * world;
}
