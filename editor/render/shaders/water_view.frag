#version 450 core
// The water as the view shows it, the fragment half (water_view.vert): a fragment on the
// other side of the surface from its line of sight's eye end is tinted as a translucent
// sheet of water over it would tint it.
layout(std140, binding = 2) uniform WaterView {
    vec4 uWaterTint;     // rgb: the water's colour; a: its opacity, 0 for no water
    vec4 uWaterGrid;
    vec4 uWaterEye;
    vec4 uWaterForward;
};

vec3 throughWater(vec3 colour, vec2 sides) {
    return uWaterTint.a > 0.0 && (sides.x > 0.0) != (sides.y > 0.0)
               ? mix(colour, uWaterTint.rgb, uWaterTint.a)
               : colour;
}
