#version 330 core
// A quiet vertical gradient behind the mesh (a studio backdrop: lighter above).
in float height;
out vec4 frag_color;

uniform vec3 top_color;    // sRGB
uniform vec3 bottom_color; // sRGB

void main() { frag_color = vec4(mix(bottom_color, top_color, clamp(height, 0.0, 1.0)), 1.0); }
