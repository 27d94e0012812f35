// One name for each thing. Every option enum has one table of (value, name, label): the name is
// what the command line, the settings file and the JSON write ("snert", "raybox"), the label
// what the app's combos and the figures show ("SNERT", "ray-box"). Adding a value to an enum
// means adding one row here, and every reader and writer follows.
//
// The tables are found by argument-dependent lookup, name_table(E{}), so the renderer's enums
// (shading, view presets) get theirs beside their declarations with the same helpers.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "metrics.h"
#include "relaxation.h"
#include "segmentation.h"
#include "triangulation.h"

namespace snert {

// What produced a mesh: Marching Cubes or one of the relaxed nets.
enum class Method { MarchingCubes, Sna, Gradient, Snert };
Method method_of(RelaxMode mode);
std::optional<RelaxMode> relax_mode_of(Method method); // empty for Marching Cubes

template <class E> struct Named {
    E value;
    std::string_view name;  // machine name: command line, settings, JSON
    std::string_view label; // what people read: combos, titles, tables
};

std::span<const Named<Method>> name_table(Method);
std::span<const Named<InsideIs>> name_table(InsideIs);
std::span<const Named<RelaxMode>> name_table(RelaxMode);
std::span<const Named<Schedule>> name_table(Schedule);
std::span<const Named<Constraint>> name_table(Constraint);
std::span<const Named<GradientMethod>> name_table(GradientMethod);
std::span<const Named<TriangulationRule>> name_table(TriangulationRule);
std::span<const Named<ShapeMeasure>> name_table(ShapeMeasure);

template <class E> std::string_view name_of(E value) {
    for (const Named<E>& row : name_table(E{}))
        if (row.value == value) return row.name;
    return "?";
}

template <class E> std::string_view label_of(E value) {
    for (const Named<E>& row : name_table(E{}))
        if (row.value == value) return row.label;
    return "?";
}

// The value named `name` (exact, lower case), or empty.
template <class E> std::optional<E> parse_name(std::string_view name) {
    for (const Named<E>& row : name_table(E{}))
        if (row.name == name) return row.value;
    return std::nullopt;
}

// "sna|gradient|snert": for help texts and error messages.
template <class E> std::string name_choices(std::string_view separator = "|") {
    std::string text;
    for (const Named<E>& row : name_table(E{})) {
        if (!text.empty()) text += separator;
        text += row.name;
    }
    return text;
}

} // namespace snert
