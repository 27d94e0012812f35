// The end every reader shares: checked geometry, the grid, VolumeInfo, the NaN policy.
#include "volume_result.h"

#include <cmath>
#include <stdexcept>

#include "core/huge_pages.h"
#include "volume_checks.h"

namespace snert::detail {

namespace {

bool is_float(ScalarType type) {
    return type == ScalarType::Float32 || type == ScalarType::Float64;
}

// Positive finite spacing, finite origin, invertible direction.
void check_geometry(const std::string& path, const Geometry& g) {
    for (int a = 0; a < 3; ++a)
        if (!(g.spacing[a] > 0.0f) || !std::isfinite(g.spacing[a]))
            throw std::runtime_error(path + ": invalid spacing " + std::to_string(g.spacing[a]) +
                                     " along axis " + std::to_string(a));
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(g.origin[a]))
            throw std::runtime_error(path + ": invalid (non-finite) origin");
    const float det = glm::determinant(g.direction);
    if (!std::isfinite(det) || std::abs(det) < 1e-6f)
        throw std::runtime_error(path + ": invalid direction cosines (not invertible)");
}

} // namespace

Volume allocate_volume(const std::string& path, glm::ivec3 dims, const Geometry& g) {
    check_geometry(path, g);
    Volume v;
    v.dims = dims;
    v.spacing = g.spacing;
    v.origin = g.origin;
    v.direction = g.direction;
    detail::resize_on_huge_pages(v.samples, v.voxel_count());
    return v;
}

VolumeInfo make_info(const std::string& path, const std::string& format, ScalarType type,
                     const Volume& volume) {
    VolumeInfo info;
    info.path = path;
    info.format = format;
    info.scalar_type = scalar_type_name(type);
    info.dims = volume.dims;
    info.spacing = volume.spacing;
    info.origin = volume.origin;
    info.direction = volume.direction;
    return info;
}

void finish_volume(LoadedVolume& loaded, ScalarType type, const LoadOptions& options) {
    if (is_float(type))
        loaded.info.nonfinite =
            apply_nonfinite_policy(loaded.volume, options.nonfinite, loaded.info.path).total();
    loaded.info.range = value_range(loaded.volume);
    options.progress.update(1.0f);
}

} // namespace snert::detail
