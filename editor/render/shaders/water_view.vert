#version 450 core
// The water as the view shows it (view/water_view.h, whose C++ twin this is), the vertex
// half: how far below the water surface a vertex lies, and the eye's end of its line of sight
// (the eye, or for an orthographic view the vertex's foot on the plane through the eye).
// Linked into every program that draws into the 3D view (bodies, lines, the water graph),
// whose fragments interpolate the two and tint themselves where their signs differ
// (water_view.frag). Per vertex, not per fragment: on llvmpipe the heights' fetches per
// fragment cost more than the sheet of water they replace; between vertices the surface is
// taken as flat (exact on flat water; lines are drawn in pieces no longer than a cell).
layout(std140, binding = 2) uniform WaterView {
    vec4 uWaterTint;     // rgb: the water's colour; a: its opacity, 0 for no water
    vec4 uWaterGrid;     // x0, z0 of the first sample, the step (m), the cells a side
    vec4 uWaterEye;      // the eye; w: 1 for an orthographic view
    vec4 uWaterForward;  // the view direction (unit)
};
layout(binding = 3) uniform sampler2D uWaterHeights;  // (cells + 1)^2, R32F, texel (i, j)

float waterHeightAt(vec2 xz) {
    float cells = uWaterGrid.w;
    vec2 g = clamp((xz - uWaterGrid.xy) / uWaterGrid.z, vec2(0.0), vec2(cells));
    ivec2 c = min(ivec2(floor(g)), ivec2(int(cells) - 1));
    vec2 f = g - vec2(c);
    float h00 = texelFetch(uWaterHeights, c, 0).r;
    float h11 = texelFetch(uWaterHeights, c + ivec2(1, 1), 0).r;
    // The cell's two triangles, split along its diagonal from (i, j) to (i + 1, j + 1).
    if (f.x >= f.y) {
        float h10 = texelFetch(uWaterHeights, c + ivec2(1, 0), 0).r;
        return h00 + f.x * (h10 - h00) + f.y * (h11 - h10);
    }
    float h01 = texelFetch(uWaterHeights, c + ivec2(0, 1), 0).r;
    return h00 + f.y * (h01 - h00) + f.x * (h11 - h01);
}

// x: the depth of `world` under the surface; y: that of its line of sight's eye end (m, < 0
// above the water). Zero without water.
vec2 waterSides(vec3 world) {
    if (uWaterTint.a <= 0.0) return vec2(0.0);
    vec3 start = uWaterEye.w > 0.5
                     ? world - uWaterForward.xyz * dot(world - uWaterEye.xyz, uWaterForward.xyz)
                     : uWaterEye.xyz;
    return vec2(waterHeightAt(world.xz) - world.y, waterHeightAt(start.xz) - start.y);
}
