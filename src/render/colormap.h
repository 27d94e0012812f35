// The colours of the figures: a perceptual colormap for triangle quality, the highlight for
// poor triangles, and one colour per method for titles and histograms.
//
// All colours are sRGB in [0, 1] (what a PNG stores); shaders linearise before lighting.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "core/names.h"

namespace snert::render {

// Viridis-like map (dark blue-violet at 0, green at 0.6, yellow at 1): perceptually ordered,
// readable in grey scale and by colour-blind readers. Interpolates the published viridis
// values at 9 evenly spaced stops. t is clamped to [0, 1]; NaN maps to 0.
glm::vec3 viridis(float t);

// n samples of viridis over [0, 1] as RGBA8 (alpha 255), for a 1D texture. n >= 2.
std::vector<std::uint8_t> viridis_rgba8(int n);

// Diverging map for signed values (Moreland's cool to warm): blue at 0, a light grey at 0.5, red
// at 1, both halves of about the same lightness ramp. t is clamped to [0, 1]; NaN maps to 0.5.
glm::vec3 cool_warm(float t);
std::vector<std::uint8_t> cool_warm_rgba8(int n);

// The colour quality shading gives `value` of `measure` over `scale` (core/metrics.h): viridis,
// or cool_warm for a diverging scale, across it; the shapes under `threshold` in
// kPoorQualityColor.
glm::vec3 measure_color(ShapeMeasure measure, float value, float threshold,
                        const MeasureScale& scale);

// Triangles whose quality is under the threshold are drawn in this colour, which viridis
// never produces (a saturated red).
inline constexpr glm::vec3 kPoorQualityColor{0.87f, 0.11f, 0.13f};

// Surface colour for flat and smooth shading: a light clay tone that shows shading well.
inline constexpr glm::vec3 kSurfaceColor{0.80f, 0.77f, 0.71f};

// Series colours (Okabe-Ito palette, safe for colour-blind readers): Marching Cubes orange,
// the relaxed net blue, a third method green.
glm::vec3 method_color(Method method);

} // namespace snert::render
