#include "report.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <ostream>

#include "core/input_error.h"
#include "core/phantom.h"
#include "io/atomic_file.h"
#include "io/load_volume.h"
#include "options.h"

#ifndef SNERT_VERSION
#define SNERT_VERSION "unknown"
#endif

namespace snert::cli {

Measured measured(const Source& source, float iso) {
    Measured m;
    m.name = source.spec.input;
    m.iso = iso;
    m.reference = accuracy_reference(source, iso);
    m.mask = source.mask != nullptr;
    return m;
}

std::vector<Method> compared_methods(std::optional<RelaxMode> mode) {
    if (mode) return {Method::MarchingCubes, method_of(*mode)};
    return {Method::MarchingCubes, Method::Sna, Method::Snert};
}

MethodResult run_source_method(Method method, const Source& source, const PipelineOptions& options,
                               const Measured& m, const Progress& progress) {
    PipelineOptions o = options;
    o.measure.reference_volume = m.reference.volume;
    return run_method(method, *source.volume, source.mask.get(), o, m.reference.distance, progress);
}

void require_surface(const MethodResult& result, const Measured& m) {
    if (result.mesh.triangle_count() > 0) return;
    throw InputError(m.name + ": the surface at iso " + format_number(m.iso) +
                     " is empty (the volume is all inside or all outside)");
}

std::vector<MethodResult> run_compared_methods(const std::vector<Method>& methods,
                                               const Source& source, const PipelineOptions& options,
                                               const Measured& m,
                                               const std::function<Progress(Method)>& stage) {
    std::vector<MethodResult> results(methods.size());
    auto run = [&](std::size_t i) {
        results[i] = run_source_method(methods[i], source, options, m, stage(methods[i]));
        require_surface(results[i], m);
    };
    for (std::size_t i = 0; i < methods.size(); ++i)
        if (methods[i] != Method::MarchingCubes) run(i);
    for (std::size_t i = 0; i < methods.size(); ++i)
        if (methods[i] == Method::MarchingCubes) run(i);
    measure_against_marching_cubes(results, *source.volume);
    return results;
}

namespace {

nlohmann::json number_or_null(std::optional<double> v) {
    if (!v || !std::isfinite(*v)) return nullptr;
    return *v;
}

// A float as the shortest decimal that reads back as the same float (1e-4, not
// 9.999999747378752e-05).
double shortest(float value) {
    if (!std::isfinite(value)) return double(value);
    char text[32];
    for (int digits = 6; digits <= 9; ++digits) {
        std::snprintf(text, sizeof text, "%.*g", digits, double(value));
        if (std::strtof(text, nullptr) == value) return std::strtod(text, nullptr);
    }
    return double(value);
}

nlohmann::json shortest(glm::vec3 v) {
    return {shortest(v.x), shortest(v.y), shortest(v.z)};
}

template <class E> std::string name(E value) {
    return std::string(name_of(value));
}

bool is_net(const MethodResult& r) {
    return r.method != Method::MarchingCubes;
}

double sliver_share(const MethodMetrics& m) {
    return m.triangles == 0 ? 0.0 : double(m.quality.slivers) / double(m.triangles);
}

} // namespace

nlohmann::json fe_json(const FeReadiness& fe) {
    nlohmann::json j;
    j["min_angle_below_15"] = fe.min_angle_below_15;
    j["min_angle_below_30"] = fe.min_angle_below_30;
    j["max_angle_above_120"] = fe.max_angle_above_120;
    j["radius_ratio_min"] = fe.radius_ratio_min;
    j["radius_ratio_max"] = fe.radius_ratio_max;
    // Infinite with a degenerate triangle, which JSON cannot write: null then.
    j["aspect_ratio_min"] = number_or_null(fe.aspect_ratio_min);
    j["aspect_ratio_max"] = number_or_null(fe.aspect_ratio_max);
    j["closed"] = fe.closed;
    j["manifold"] = fe.manifold;
    j["self_intersections"] = fe.self_intersections;
    return j;
}

std::string accuracy_against(const Measured& m) {
    if (m.reference.analytic) return "the exact surface of the phantom";
    const std::string surface = "the trilinear iso-surface I = " + format_number(m.iso) +
                                " of the grey values (first-order distance |I - iso| / |grad I|)";
    if (!m.mask) return surface;
    // MC runs on the label's mask, the nets' gradient term on the grey values: neither is on
    // this surface by construction, and it is not the mask's own boundary.
    return surface + ", not the label mask's boundary";
}

nlohmann::json method_json(const MethodResult& r, const Measured& measured) {
    const MethodMetrics& m = r.metrics;
    nlohmann::json j;
    j["vertices"] = m.vertices;
    j["triangles"] = m.triangles;
    j["quality_mean"] = m.quality.mean;
    j["quality_min"] = m.quality.min;
    j["quality_hist"] = m.quality.histogram;
    j["quality60_mean"] = m.quality.quality60_mean;
    j["radius_ratio_mean"] = m.quality.radius_ratio_mean;
    j["min_angle_min"] = m.quality.min_angle_min;
    j["min_angle_deg"] = m.quality.min_angle_min;
    j["degenerate"] = m.quality.degenerate;
    j["slivers"] = sliver_share(m);
    j["smoothness"] = m.smoothness;
    const std::optional<Accuracy>& a = m.accuracy;
    j["accuracy_vertices"] = number_or_null(a ? std::optional(a->vertices_mean) : std::nullopt);
    j["accuracy_vertices_max"] = number_or_null(a ? std::optional(a->vertices_max) : std::nullopt);
    j["accuracy_faces"] = number_or_null(a ? std::optional(a->faces_mean) : std::nullopt);
    j["accuracy_faces_max"] = number_or_null(a ? std::optional(a->faces_max) : std::nullopt);
    j["accuracy_surface"] = number_or_null(a ? std::optional(a->surface_mean) : std::nullopt);
    j["accuracy_surface_max"] = number_or_null(a ? std::optional(a->surface_max) : std::nullopt);
    // Distance to the Marching Cubes surface of the same run (voxels); null for MC itself.
    const std::optional<Accuracy>& d = m.to_marching_cubes;
    j["to_mc_vertices"] = number_or_null(d ? std::optional(d->vertices_mean) : std::nullopt);
    j["to_mc_surface"] = number_or_null(d ? std::optional(d->surface_mean) : std::nullopt);
    j["to_mc_surface_max"] = number_or_null(d ? std::optional(d->surface_max) : std::nullopt);
    j["accuracy_reference"] = measured.reference.analytic ? "analytic" : "first-order";
    j["accuracy_against"] = accuracy_against(measured);
    j["watertight"] = m.topology.watertight;
    j["manifold"] = m.topology.manifold;
    j["boundary_edges"] = m.topology.boundary_edges;
    j["boundary_edges_off_border"] = m.boundary_edges_off_border;
    j["nonmanifold_edges"] = m.topology.nonmanifold_edges;
    j["nonmanifold_vertices"] = m.topology.nonmanifold_vertices;
    j["self_intersections"] = m.self_intersections;
    j["fe_ready"] = m.fe_ready;
    j["fe"] = fe_json(m.fe);
    j["oriented"] = m.topology.oriented;
    j["euler"] = m.topology.euler;
    j["area"] = m.area;
    j["volume"] = m.volume;
    j["volume_error_percent"] =
        m.volume_error ? number_or_null(100.0 * *m.volume_error) : nlohmann::json(nullptr);
    j["ms"] = m.ms;
    // The relaxation's own numbers; null for Marching Cubes, which has none.
    j["iterations"] = is_net(r) ? nlohmann::json(m.iterations) : nlohmann::json(nullptr);
    j["converged"] = is_net(r) ? nlohmann::json(m.converged) : nlohmann::json(nullptr);
    j["final_max_move"] = is_net(r) ? number_or_null(m.final_max_move) : nlohmann::json(nullptr);
    // Node moves the step safeguard shortened (summed over iterations): what validity cost.
    j["shortened_moves"] = is_net(r) ? nlohmann::json(m.shortened_moves) : nlohmann::json(nullptr);
    return j;
}

namespace {

std::string yes_no(bool v) {
    return v ? "yes" : "no";
}

std::string exponent(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.2e", v);
    return b;
}

// Quality, smoothness, accuracy and volume, one row per method.
void print_quality_table(std::ostream& out, const std::vector<MethodResult>& results) {
    char line[512];
    std::snprintf(line, sizeof line, "  %-8s %9s %7s %7s %7s %7s %9s %9s %9s %9s %9s %8s %8s\n",
                  "method", "triangles", "q", "q_min", "q60", "r_ratio", "smooth", "accV", "accF",
                  "accS", "to_mc", "vol_err%", "ms");
    out << line;
    for (const MethodResult& r : results) {
        const MethodMetrics& m = r.metrics;
        auto acc = [&](double Accuracy::*field) {
            return m.accuracy ? exponent((*m.accuracy).*field) : std::string("-");
        };
        const std::string to_mc =
            m.to_marching_cubes ? exponent(m.to_marching_cubes->surface_mean) : std::string("-");
        std::string volume_error = "-";
        if (m.volume_error) {
            char b[32];
            std::snprintf(b, sizeof b, "%+.3f", 100.0 * *m.volume_error);
            volume_error = b;
        }
        std::snprintf(line, sizeof line,
                      "  %-8s %9zu %7.3f %7.3f %7.3f %7.3f %9.2e %9s %9s %9s %9s %8s %8.1f\n",
                      std::string(name_of(r.method)).c_str(), m.triangles, m.quality.mean,
                      m.quality.min, m.quality.quality60_mean, m.quality.radius_ratio_mean,
                      m.smoothness, acc(&Accuracy::vertices_mean).c_str(),
                      acc(&Accuracy::faces_mean).c_str(), acc(&Accuracy::surface_mean).c_str(),
                      to_mc.c_str(), volume_error.c_str(), m.ms);
        out << line;
    }
}

// What a finite-element mesher needs, one row per method, and the relaxation's end.
void print_fe_table(std::ostream& out, const std::vector<MethodResult>& results) {
    char line[512];
    std::snprintf(line, sizeof line, "  %-8s %6s %8s %7s %7s %7s %7s %8s %7s %6s %8s %6s %9s %9s\n",
                  "method", "closed", "manifold", "nm_edge", "nm_vert", "holes", "self_x",
                  "slivers%", "min_ang", "degen", "fe_ready", "iters", "converged", "max_move");
    out << line;
    for (const MethodResult& r : results) {
        const MethodMetrics& m = r.metrics;
        std::string iterations = "-", converged = "-", max_move = "-";
        if (is_net(r)) {
            iterations = std::to_string(m.iterations);
            converged = yes_no(m.converged);
            max_move = exponent(m.final_max_move);
        }
        std::snprintf(line, sizeof line,
                      "  %-8s %6s %8s %7zu %7zu %7zu %7zu %8.2f %7.2f %6zu %8s %6s %9s %9s\n",
                      std::string(name_of(r.method)).c_str(), yes_no(m.topology.watertight).c_str(),
                      yes_no(m.topology.manifold).c_str(), m.topology.nonmanifold_edges,
                      m.topology.nonmanifold_vertices, m.boundary_edges_off_border,
                      m.self_intersections, 100.0 * sliver_share(m), m.quality.min_angle_min,
                      m.quality.degenerate, yes_no(m.fe_ready).c_str(), iterations.c_str(),
                      converged.c_str(), max_move.c_str());
        out << line;
    }
}

// The FE-readiness summary, one row per method.
void print_fe_summary_table(std::ostream& out, const std::vector<MethodResult>& results) {
    char line[512];
    std::snprintf(line, sizeof line, "  %-8s %8s %8s %9s %15s %17s %6s %8s %7s\n", "method",
                  "min<15%", "min<30%", "max>120%", "r_ratio", "aspect", "closed", "manifold",
                  "self_x");
    out << line;
    for (const MethodResult& r : results) {
        const FeReadiness& fe = r.metrics.fe;
        char range[2][64];
        std::snprintf(range[0], sizeof range[0], "%.3f-%.3f", fe.radius_ratio_min,
                      fe.radius_ratio_max);
        std::snprintf(range[1], sizeof range[1], "%.3f-%.4g", fe.aspect_ratio_min,
                      fe.aspect_ratio_max);
        std::snprintf(line, sizeof line, "  %-8s %8.2f %8.2f %9.2f %15s %17s %6s %8s %7zu\n",
                      std::string(name_of(r.method)).c_str(), 100.0 * fe.min_angle_below_15,
                      100.0 * fe.min_angle_below_30, 100.0 * fe.max_angle_above_120, range[0],
                      range[1], yes_no(fe.closed).c_str(), yes_no(fe.manifold).c_str(),
                      fe.self_intersections);
        out << line;
    }
}

} // namespace

void print_table(std::ostream& out, const std::string& title,
                 const std::vector<MethodResult>& results, const Measured& measured) {
    out << title << "\n";
    print_quality_table(out, results);
    out << "  q = smallest / largest angle, q60 = smallest angle / 60 degrees, r_ratio = 2r/R; "
           "smooth = mean |2 pi - angle sum| in radians; vol_err in percent of the exact "
           "volume; ms = milliseconds to build the mesh\n"
        << "  accuracy in voxels against " << accuracy_against(measured)
        << ": accV at the vertices (Marching Cubes' lie on the iso-surface by construction), "
           "accF at the face centres, accS over the whole surface (area-weighted, "
        << kSurfaceSampleSplit * kSurfaceSampleSplit
        << " points a triangle); to_mc: mean distance over the surface to the Marching Cubes "
           "mesh (voxels)\n";
    print_fe_table(out, results);
    out << "  closed: no boundary edge; manifold: edges and vertices, a boundary allowed; holes: "
           "boundary edges off the volume border; self_x: intersecting triangle pairs; slivers: "
           "q < "
        << format_number(kSliverQuality)
        << " in percent; min_ang in degrees; degen: zero-area triangles; max_move: the last "
           "iteration's largest node move in voxels\n";
    print_fe_summary_table(out, results);
    out << "  FE readiness: percent of triangles with the smallest angle under 15 and 30 "
           "degrees and the largest over 120 degrees; ranges (min-max) of the radius ratio 2r/R "
           "(best 1) and of Verdict's aspect ratio (longest edge * perimeter / (4 sqrt(3) "
           "area), best 1, inf with a degenerate triangle)\n";
}

nlohmann::json input_json(const Source& source) {
    const SourceSpec& spec = source.spec;
    nlohmann::json j;
    if (const std::string_view name = phantom_spec_name(spec.input); !name.empty()) {
        j["phantom"] = std::string(name);
        j["size"] = spec.phantom_size;
    } else {
        j["path"] = spec.input;
        if (source.info) j["format"] = source.info->format;
    }
    if (spec.raw) {
        const RawOptions& raw = *spec.raw;
        j["raw"] = {{"dims", {raw.dims.x, raw.dims.y, raw.dims.z}},
                    {"type", scalar_type_name(raw.type)},
                    {"spacing", shortest(raw.spacing)},
                    {"endian", raw.endian == Endian::Little ? "little" : "big"}};
    }
    if (source.info && !source.info->series_uid.empty()) j["series"] = source.info->series_uid;
    if (!spec.labels.empty()) j["labels"] = spec.labels;
    if (spec.label) {
        j["label"] = *spec.label;
        for (const LabelEntry& e : source.labels_present)
            if (e.value == *spec.label && !e.name.empty()) j["label_name"] = e.name;
    }
    if (source.volume) {
        const Volume& v = *source.volume;
        const glm::ivec3 dims = read_dims(source);
        j["dims"] = {dims.x, dims.y, dims.z};
        j["close_border"] = source.border_closed;
        j["spacing"] = shortest(v.spacing);
        if (spec.isotropic) j["isotropic"] = shortest(v.spacing.x); // the edge used, mm
    }
    return j;
}

nlohmann::json relaxation_json(const RelaxOptions& r) {
    return {{"mode", name(r.mode)},
            {"iterations", r.max_iterations},
            {"smoothing_weight", shortest(r.smoothing_weight)},
            {"gradient_weight", shortest(r.gradient_weight)},
            {"schedule", name(r.schedule)},
            {"constraint", name(r.constraint)},
            {"gradient", name(r.gradient)},
            {"sigma", shortest(r.gradient_sigma)},
            {"epsilon", shortest(r.epsilon)},
            {"triangulation", name(r.triangulation)},
            {"guard", r.keep_valid}};
}

nlohmann::json provenance_json(std::string_view command, nlohmann::json input,
                               std::optional<float> iso, std::optional<InsideIs> inside,
                               const RelaxOptions& relax) {
    nlohmann::json j;
    j["version"] = SNERT_VERSION;
    j["command"] = std::string(command);
    j["input"] = std::move(input);
    j["iso"] = iso ? nlohmann::json(shortest(*iso)) : nlohmann::json(nullptr);
    j["inside"] = inside ? nlohmann::json(name(*inside)) : nlohmann::json(nullptr);
    j["relaxation"] = relaxation_json(relax);
    return j;
}

void write_json(const std::string& path, const nlohmann::json& json) {
    if (path == "-") {
        std::cout << json.dump(2) << "\n" << std::flush;
        return;
    }
    write_file_atomically(path, [&](std::ostream& out) { out << json.dump(2) << "\n"; });
}

} // namespace snert::cli
