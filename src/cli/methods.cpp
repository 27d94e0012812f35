#include "methods.h"

#include <cmath>
#include <cstdio>
#include <ostream>

#include "io/atomic_file.h"

namespace snert::cli {

std::vector<Method> requested_methods(const Args& args) {
    if (args.has("mode"))
        return {Method::MarchingCubes,
                method_of(*parse_name<RelaxMode>(args.choice("mode", "snert", {"sna", "gradient", "snert"})))};
    return {Method::MarchingCubes, Method::Sna, Method::Snert};
}

MethodResult run_method(const Input& input, const PipelineOptions& base, Method method,
                        const Progress& progress) {
    PipelineOptions options = base;
    options.relax.iso = input.iso;
    if (const auto mode = relax_mode_of(method)) options.relax.mode = *mode;
    if (input.labels) {
        // The label's mask decides the topology; MC runs on it at 0.5 as 3D Slicer does.
        const Volume mask = mask_volume(*input.labels, input.volume);
        if (method == Method::MarchingCubes) {
            options.iso = 0.5f;
            options.inside = InsideIs::Above;
            return run_marching_cubes(mask, options, input.reference, progress);
        }
        return run_surface_net(input.volume, *input.labels, options, input.reference, progress);
    }
    if (method == Method::MarchingCubes) return run_marching_cubes(input.volume, options, input.reference, progress);
    const Segmentation segmentation = segment_threshold(input.volume, options.iso, options.inside);
    return run_surface_net(input.volume, segmentation, options, input.reference, progress);
}

void require_surface(const MethodResult& result, const Input& input) {
    if (result.mesh.triangle_count() > 0) return;
    char iso[32];
    std::snprintf(iso, sizeof iso, "%g", double(input.iso));
    throw std::runtime_error(input.name + ": the surface at iso " + iso +
                             " is empty (the volume is all inside or all outside)");
}

namespace {

nlohmann::json number_or_null(std::optional<double> v) {
    if (!v || !std::isfinite(*v)) return nullptr;
    return *v;
}

bool is_net(const MethodResult& r) {
    return r.method != Method::MarchingCubes;
}

double sliver_share(const MethodMetrics& m) {
    return m.triangles == 0 ? 0.0 : double(m.quality.slivers) / double(m.triangles);
}

std::string format_iso(float iso) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(iso));
    return text;
}

} // namespace

std::string accuracy_against(const Input& input) {
    if (input.analytic_reference) return "the exact surface of the phantom";
    const std::string surface = "the trilinear iso-surface I = " + format_iso(input.iso) +
                                " of the grey values (first-order distance |I - iso| / |grad I|)";
    if (!input.labels) return surface;
    // MC runs on the label's mask, the nets' gradient term on the grey values: neither is on
    // this surface by construction, and it is not the mask's own boundary.
    return surface + ", not the label mask's boundary";
}

nlohmann::json method_json(const MethodResult& r, const Input& input) {
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
    j["accuracy_reference"] = input.analytic_reference ? "analytic" : "first-order";
    j["accuracy_against"] = accuracy_against(input);
    j["watertight"] = m.topology.watertight;
    j["manifold"] = m.topology.manifold;
    j["boundary_edges"] = m.topology.boundary_edges;
    j["boundary_edges_off_border"] = m.boundary_edges_off_border;
    j["nonmanifold_edges"] = m.topology.nonmanifold_edges;
    j["nonmanifold_vertices"] = m.topology.nonmanifold_vertices;
    j["self_intersections"] = m.self_intersections;
    j["fe_ready"] = m.fe_ready;
    j["oriented"] = m.topology.oriented;
    j["euler"] = m.topology.euler;
    j["area"] = m.area;
    j["volume"] = m.volume;
    if (input.reference_volume > 0) {
        // Phantom volumes are in voxels^3; spacing is 1 for phantoms, so world = voxels.
        j["volume_error_percent"] =
            100.0 * (m.volume - input.reference_volume) / input.reference_volume;
    } else {
        j["volume_error_percent"] = nullptr;
    }
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

// Quality, smoothness, accuracy and volume, one row per method.
void print_quality_table(std::ostream& out, const std::vector<MethodResult>& results,
                         const Input& input) {
    char line[512];
    std::snprintf(line, sizeof line, "  %-8s %9s %7s %7s %7s %7s %9s %9s %9s %9s %8s %8s\n",
                  "method", "triangles", "q", "q_min", "q60", "r_ratio", "smooth", "accV", "accF",
                  "accS", "vol_err%", "ms");
    out << line;
    for (const MethodResult& r : results) {
        const MethodMetrics& m = r.metrics;
        auto acc = [&](double Accuracy::*field) {
            if (!m.accuracy) return std::string("-");
            char b[32];
            std::snprintf(b, sizeof b, "%.2e", (*m.accuracy).*field);
            return std::string(b);
        };
        std::string volume_error = "-";
        if (input.reference_volume > 0) {
            char b[32];
            std::snprintf(b, sizeof b, "%+.3f",
                          100.0 * (m.volume - input.reference_volume) / input.reference_volume);
            volume_error = b;
        }
        std::snprintf(line, sizeof line,
                      "  %-8s %9zu %7.3f %7.3f %7.3f %7.3f %9.2e %9s %9s %9s %8s %8.1f\n",
                      std::string(name_of(r.method)).c_str(), m.triangles, m.quality.mean, m.quality.min,
                      m.quality.quality60_mean, m.quality.radius_ratio_mean, m.smoothness,
                      acc(&Accuracy::vertices_mean).c_str(), acc(&Accuracy::faces_mean).c_str(),
                      acc(&Accuracy::surface_mean).c_str(), volume_error.c_str(), m.ms);
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
            char b[32];
            std::snprintf(b, sizeof b, "%.2e", m.final_max_move);
            max_move = b;
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

} // namespace

void print_table(std::ostream& out, const std::string& title,
                 const std::vector<MethodResult>& results, const Input& input) {
    out << title << "\n";
    print_quality_table(out, results, input);
    out << "  accuracy in voxels against " << accuracy_against(input)
        << ": accV at the vertices (Marching Cubes' lie on the iso-surface by construction), "
           "accF at the face centres, accS over the whole surface (area-weighted, "
        << kSurfaceSampleSplit * kSurfaceSampleSplit << " points a triangle)\n";
    print_fe_table(out, results);
    out << "  closed: no boundary edge; manifold: edges and vertices, a boundary allowed; holes: "
           "boundary edges off the volume border; self_x: intersecting triangle pairs; slivers: "
           "q < "
        << kSliverQuality << "; min_ang in degrees; degen: zero-area triangles\n";
}

void write_json(const std::string& path, const nlohmann::json& json) {
    write_file_atomically(path, [&](std::ostream& out) { out << json.dump(2) << "\n"; });
}

} // namespace snert::cli
