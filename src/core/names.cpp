#include "names.h"

namespace snert {

namespace {

constexpr Named<Method> kMethods[] = {
    {Method::MarchingCubes, "mc", "Marching Cubes"},
    {Method::Sna, "sna", "SNA"},
    {Method::Gradient, "gradient", "Gradient"},
    {Method::Snert, "snert", "SNERT"},
};
constexpr Named<InsideIs> kInside[] = {
    {InsideIs::Above, "above", "above iso (bright object)"},
    {InsideIs::Below, "below", "below iso (dark object)"},
};
// Same names as the nets' methods, so `--mode snert` runs the method `snert`.
constexpr Named<RelaxMode> kModes[] = {
    {RelaxMode::Averaging, "sna", "SNA: averaging (eq. 1-2)"},
    {RelaxMode::Gradient, "gradient", "Gradient step (eq. 3-4)"},
    {RelaxMode::Snert, "snert", "SNERT: projected averaging + gradient (eq. 5-6)"},
};
constexpr Named<Schedule> kSchedules[] = {
    {Schedule::Simultaneous, "simultaneous", "both at once"},
    {Schedule::SmoothingFirst, "smoothing-first", "smoothing first"},
};
constexpr Named<Constraint> kConstraints[] = {
    {Constraint::RayBox, "raybox", "ray-box (shorten the move)"},
    {Constraint::Clip, "clip", "clip x, y, z (original)"},
};
constexpr Named<GradientMethod> kGradients[] = {
    {GradientMethod::Central, "central", "central differences"},
    {GradientMethod::Gaussian, "gaussian", "Gaussian derivative"},
    {GradientMethod::Trilinear, "trilinear", "trilinear field"},
};
constexpr Named<TriangulationRule> kTriangulations[] = {
    {TriangulationRule::ShorterDiagonal, "shorter", "shorter diagonal"},
    {TriangulationRule::Delaunay, "delaunay", "Delaunay"},
};
// The labels are the symbols legends and axes use ("q60 < 0.25").
constexpr Named<ShapeMeasure> kShapeMeasures[] = {
    {ShapeMeasure::Quality, "q", "q"},
    {ShapeMeasure::Quality60, "q60", "q60"},
    {ShapeMeasure::RadiusRatio, "radius-ratio", "radius ratio"},
    {ShapeMeasure::DistanceIso, "distance-iso", "distance to the iso-surface"},
    {ShapeMeasure::DistanceOther, "distance-other", "distance to the other mesh"},
};

} // namespace

Method method_of(RelaxMode mode) {
    switch (mode) {
    case RelaxMode::Averaging:
        return Method::Sna;
    case RelaxMode::Gradient:
        return Method::Gradient;
    case RelaxMode::Snert:
        return Method::Snert;
    }
    return Method::Snert;
}

std::optional<RelaxMode> relax_mode_of(Method method) {
    switch (method) {
    case Method::MarchingCubes:
        return std::nullopt;
    case Method::Sna:
        return RelaxMode::Averaging;
    case Method::Gradient:
        return RelaxMode::Gradient;
    case Method::Snert:
        return RelaxMode::Snert;
    }
    return std::nullopt;
}

std::span<const Named<Method>> name_table(Method) {
    return kMethods;
}
std::span<const Named<InsideIs>> name_table(InsideIs) {
    return kInside;
}
std::span<const Named<RelaxMode>> name_table(RelaxMode) {
    return kModes;
}
std::span<const Named<Schedule>> name_table(Schedule) {
    return kSchedules;
}
std::span<const Named<Constraint>> name_table(Constraint) {
    return kConstraints;
}
std::span<const Named<GradientMethod>> name_table(GradientMethod) {
    return kGradients;
}
std::span<const Named<TriangulationRule>> name_table(TriangulationRule) {
    return kTriangulations;
}
std::span<const Named<ShapeMeasure>> name_table(ShapeMeasure) {
    return kShapeMeasures;
}

} // namespace snert
