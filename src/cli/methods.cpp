#include "methods.h"

#include <cmath>
#include <cstdio>
#include <ostream>

#include "core/atomic_file.h"

namespace snert::cli {

std::vector<std::string> requested_methods(const Args& args) {
    if (auto mode = args.value("mode")) return {"mc", *mode};
    return {"mc", "sna", "snert"};
}

MethodResult run_method(const Input& input, const PipelineOptions& base, const std::string& method,
                        const Progress& progress) {
    PipelineOptions options = base;
    options.relax.iso = input.iso;
    options.relax.mode = method == "sna"        ? RelaxMode::Averaging
                         : method == "gradient" ? RelaxMode::Gradient
                                                : RelaxMode::Snert;
    if (input.labels) {
        // The label's mask decides the topology; MC runs on it at 0.5 as 3D Slicer does.
        const Volume mask = mask_volume(*input.labels, input.volume);
        if (method == "mc") {
            options.iso = 0.5f;
            options.inside = InsideIs::Above;
            return run_marching_cubes(mask, options, input.reference, progress);
        }
        return run_surface_net(input.volume, *input.labels, options, input.reference, progress);
    }
    if (method == "mc") return run_marching_cubes(input.volume, options, input.reference, progress);
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

} // namespace

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
    j["degenerate"] = m.quality.degenerate;
    j["smoothness"] = m.smoothness;
    const std::optional<Accuracy>& a = m.accuracy;
    j["accuracy_vertices"] = number_or_null(a ? std::optional(a->vertices_mean) : std::nullopt);
    j["accuracy_vertices_max"] = number_or_null(a ? std::optional(a->vertices_max) : std::nullopt);
    j["accuracy_faces"] = number_or_null(a ? std::optional(a->faces_mean) : std::nullopt);
    j["accuracy_faces_max"] = number_or_null(a ? std::optional(a->faces_max) : std::nullopt);
    j["accuracy_reference"] = input.analytic_reference ? "analytic" : "first-order";
    j["watertight"] = m.topology.watertight;
    j["manifold"] = m.topology.manifold;
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
    return j;
}

void print_table(std::ostream& out, const std::string& title,
                 const std::vector<MethodResult>& results, const Input& input) {
    char line[512];
    out << title << "\n";
    std::snprintf(line, sizeof line, "  %-8s %9s %7s %7s %7s %7s %6s %9s %9s %9s %8s %6s %8s\n",
                  "method", "triangles", "q", "q_min", "q60", "r_ratio", "degen", "smooth", "accV",
                  "accF", "vol_err%", "closed", "ms");
    out << line;
    for (const MethodResult& r : results) {
        const MethodMetrics& m = r.metrics;
        auto acc = [&](bool faces) {
            if (!m.accuracy) return std::string("-");
            char b[32];
            std::snprintf(b, sizeof b, "%.2e",
                          faces ? m.accuracy->faces_mean : m.accuracy->vertices_mean);
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
                      "  %-8s %9zu %7.3f %7.3f %7.3f %7.3f %6zu %9.2e %9s %9s %8s %6s %8.1f\n",
                      r.name.c_str(), m.triangles, m.quality.mean, m.quality.min,
                      m.quality.quality60_mean, m.quality.radius_ratio_mean, m.quality.degenerate,
                      m.smoothness, acc(false).c_str(), acc(true).c_str(), volume_error.c_str(),
                      m.topology.watertight ? "yes" : "no", m.ms);
        out << line;
    }
}

void write_json(const std::string& path, const nlohmann::json& json) {
    write_file_atomically(path, [&](std::ostream& out) { out << json.dump(2) << "\n"; });
}

} // namespace snert::cli
