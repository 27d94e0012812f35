#include "triangle_distances.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "parallel.h"

namespace snert {

namespace {

constexpr std::size_t kChunk = 1 << 13;

void check_indices(const Mesh& mesh) {
    if (mesh.indices.size() % 3 != 0)
        throw std::invalid_argument("triangle distances: index count is not a multiple of 3");
    if (const auto i = first_index_out_of_range(mesh))
        throw std::invalid_argument("triangle distances: index " + std::to_string(*i) +
                                    " out of range");
}

// The centroid in index space: the corners mapped, then averaged (as accuracy() does).
glm::vec3 index_centroid(const Mesh& world_mesh, const Volume& volume, std::size_t t) {
    const std::uint32_t* i = &world_mesh.indices[3 * t];
    return (world_to_index(volume, world_mesh.positions[i[0]]) +
            world_to_index(volume, world_mesh.positions[i[1]]) +
            world_to_index(volume, world_mesh.positions[i[2]])) /
           3.0f;
}

bool finite(glm::vec3 p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

} // namespace

std::vector<float> signed_iso_distances(const Mesh& world_mesh, const Volume& volume, float iso,
                                        InsideIs inside) {
    check_indices(world_mesh);
    std::vector<float> distance(world_mesh.triangle_count());
    // Inside is where I >= iso (Above): I - iso is negative outside there, so it is negated.
    const float outward = inside == InsideIs::Above ? -1.0f : 1.0f;
    for_each_chunk(distance.size(), kChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
        CellCorners kept; // neighbouring triangles mostly share a cell
        for (std::size_t t = begin; t < end; ++t) {
            const glm::vec3 c = index_centroid(world_mesh, volume, t);
            if (!finite(c)) {
                distance[t] = std::numeric_limits<float>::quiet_NaN();
                continue;
            }
            const ValueGradient here = sample_value_gradient(volume, c, kept);
            const float slope = glm::length(here.gradient);
            distance[t] = slope > 1e-12f ? outward * (here.value - iso) / slope : 0.0f;
        }
    });
    return distance;
}

std::vector<float> distances_to_other_mesh(const Mesh& world_mesh, const Mesh& other_world,
                                           const Volume& volume) {
    check_indices(world_mesh);
    std::vector<float> distance(world_mesh.triangle_count(),
                                std::numeric_limits<float>::quiet_NaN());
    if (other_world.triangle_count() == 0) return distance;
    Mesh other_index = other_world;
    for (glm::vec3& p : other_index.positions) p = world_to_index(volume, p);
    const MeshDistance to_other(other_index);
    for_each_chunk(distance.size(), kChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
        for (std::size_t t = begin; t < end; ++t)
            distance[t] = to_other(index_centroid(world_mesh, volume, t));
    });
    return distance;
}

MeasureScale distance_scale(ShapeMeasure measure, std::span<const float> first,
                            std::span<const float> second) {
    std::vector<float> magnitude;
    magnitude.reserve(first.size() + second.size());
    for (const std::span<const float> values : {first, second})
        for (const float v : values)
            if (!std::isnan(v)) magnitude.push_back(std::abs(v));
    float reach = 0.0f;
    if (!magnitude.empty()) {
        const auto k = std::ptrdiff_t(0.98 * double(magnitude.size() - 1));
        std::nth_element(magnitude.begin(), magnitude.begin() + k, magnitude.end());
        reach = magnitude[std::size_t(k)];
    }
    // 1, 2 or 5 times a power of ten: tick labels that read as round numbers.
    double range = 0.001;
    while (range < double(reach) && range < 1e3) { // 1000 voxels: past any volume
        const double decade = std::pow(10.0, std::floor(std::log10(range) + 1e-9));
        const double mantissa = std::round(range / decade);
        range = mantissa < 1.5 ? 2 * decade : mantissa < 3.5 ? 5 * decade : 10 * decade;
    }
    MeasureScale scale = measure_scale(measure);
    scale.high = float(range);
    scale.low = scale.diverging ? -float(range) : 0.0f;
    return scale;
}

PairDistances pair_distances(ShapeMeasure measure, const Mesh& first_world,
                             const Mesh& second_world, const Volume& volume, float iso,
                             InsideIs inside) {
    PairDistances pair;
    pair.measure = measure;
    if (measure == ShapeMeasure::DistanceIso) {
        pair.first = signed_iso_distances(first_world, volume, iso, inside);
        pair.second = signed_iso_distances(second_world, volume, iso, inside);
    } else if (measure == ShapeMeasure::DistanceOther) {
        pair.first = distances_to_other_mesh(first_world, second_world, volume);
        pair.second = distances_to_other_mesh(second_world, first_world, volume);
    } else {
        return pair;
    }
    pair.scale = distance_scale(measure, pair.first, pair.second);
    pair.first_summary = summarize_measure(pair.first, pair.scale);
    pair.second_summary = summarize_measure(pair.second, pair.scale);
    return pair;
}

} // namespace snert
