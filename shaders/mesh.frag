#version 330 core
// Lit surface in one of three shadings, with an optional wireframe overlay.
// Lighting is computed in linear RGB and written as sRGB: a key light from the upper left, a
// weaker fill from the right, a sky/ground hemisphere ambient and a soft highlight. Both sides
// of a surface are lit (open surfaces such as the plane show their back).
// SNERT_DIRECT (no wireframe): without the geometry shader, which costs software GL more than
// the rest together; the facet normal comes from the position's screen derivatives instead (it
// faces the viewer already) and the triangle from gl_PrimitiveID.
in FragmentData {
    vec3 position_view;
    vec3 normal_view;
#ifndef SNERT_DIRECT
    vec3 barycentric;
    flat vec3 facet_normal_view;
    flat int triangle;
#endif
} fragment_in;

out vec4 frag_color;

const int kFlat = 0;
const int kSmooth = 1;
const int kQuality = 2;

uniform int shading;
uniform vec3 surface_color;         // sRGB
uniform samplerBuffer quality;      // one float per triangle
uniform sampler1D colormap;         // sRGB
uniform float quality_threshold;    // below: poor_color
uniform float value_low;            // the value at the map's first colour
uniform float value_high;           // the value at its last colour
uniform vec3 poor_color;            // sRGB
uniform bool wireframe;
uniform float line_half_width;      // pixels on each side of an edge
uniform vec3 line_color;            // sRGB
#ifdef SNERT_DIRECT
uniform int first_triangle;         // of this draw: a mesh drawn in parts restarts gl_PrimitiveID
#endif

vec3 to_linear(vec3 c) { return pow(c, vec3(2.2)); }
vec3 to_srgb(vec3 c) { return pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)); }

const vec3 kKeyDirection = normalize(vec3(-0.35, 0.55, 0.75));
const vec3 kFillDirection = normalize(vec3(0.60, -0.25, 0.60));

// Diffuse light reaching a surface with unit normal n (view space): about 1 for a surface
// facing the viewer, so coloured data keeps its map colour where it is best lit.
vec3 diffuse_light(vec3 n) {
    vec3 ambient = mix(vec3(0.12, 0.11, 0.10), vec3(0.30, 0.31, 0.34), 0.5 + 0.5 * n.y);
    float key = 0.80 * max(dot(n, kKeyDirection), 0.0);
    float fill = 0.20 * max(dot(n, kFillDirection), 0.0);
    return ambient + vec3(key + fill);
}

// Blinn-Phong highlight of the key light seen along v.
float highlight(vec3 n, vec3 v) {
    return pow(max(dot(n, normalize(kKeyDirection + v)), 0.0), 48.0);
}

void main() {
#ifdef SNERT_DIRECT
    vec3 n;
    if (shading == kSmooth) {
        n = normalize(fragment_in.normal_view);
        if (!gl_FrontFacing) n = -n;
    } else {
        vec3 facet = cross(dFdx(fragment_in.position_view), dFdy(fragment_in.position_view));
        n = dot(facet, facet) > 0.0 ? normalize(facet) : vec3(0.0, 0.0, 1.0);
    }
    int triangle = first_triangle + gl_PrimitiveID;
#else
    vec3 n = normalize(shading == kSmooth ? fragment_in.normal_view
                                          : fragment_in.facet_normal_view);
    if (!gl_FrontFacing) n = -n;
    int triangle = fragment_in.triangle;
#endif
    vec3 v = normalize(-fragment_in.position_view);

    vec3 color;
    if (shading == kQuality) {
        float q = texelFetch(quality, triangle).r;
        // Sample the texel centres so the range's ends give the map's end colours exactly.
        float size = float(textureSize(colormap, 0));
        float t = clamp((q - value_low) / (value_high - value_low), 0.0, 1.0);
        vec3 albedo = isnan(q)                  ? surface_color // not measured (yet)
                      : q < quality_threshold ? poor_color
                                              : texture(colormap, (t * (size - 1.0) + 0.5) / size).rgb;
        // Softer lighting keeps the colours readable against the legend.
        color = to_linear(albedo) * (0.45 + 0.55 * diffuse_light(n)) + 0.05 * highlight(n, v);
    } else {
        color = to_linear(surface_color) * diffuse_light(n) + 0.18 * highlight(n, v);
    }

#ifndef SNERT_DIRECT
    if (wireframe) {
        // Distance to the nearest edge in pixels: barycentric / its screen derivative.
        vec3 pixels = fragment_in.barycentric / max(fwidth(fragment_in.barycentric), vec3(1e-6));
        float nearest = min(min(pixels.x, pixels.y), pixels.z);
        float coverage = 1.0 - smoothstep(line_half_width - 0.5, line_half_width + 0.5, nearest);
        color = mix(color, to_linear(line_color), 0.9 * coverage);
    }
#endif
    frag_color = vec4(to_srgb(color), 1.0);
}
