// What every volume reader does with its result (no ITK): the geometry a file states is
// checked, the float32 grid allocated, VolumeInfo filled, and the NaN / infinity policy and the
// value range applied at the end.
#pragma once

#include <string>

#include <glm/glm.hpp>

#include "core/volume.h"
#include "load_volume.h"
#include "sample_conversion.h"

namespace snert::detail {

// Geometry that the file states: spacing, origin, direction columns (LPS, millimetres).
struct Geometry {
    glm::vec3 spacing{1.0f};
    glm::vec3 origin{0.0f};
    glm::mat3 direction{1.0f};
};

// The float32 grid of a volume whose geometry has been read; checks the geometry first
// (positive finite spacing, finite origin, invertible direction: std::runtime_error naming
// `path` otherwise). The caller has checked `dims` and the memory.
Volume allocate_volume(const std::string& path, glm::ivec3 dims, const Geometry& g);

// VolumeInfo of a freshly read volume: path, format name, stored type and the grid.
VolumeInfo make_info(const std::string& path, const std::string& format, ScalarType type,
                     const Volume& volume);

// Applies the NaN policy (float types only), fills the value range and reports progress 1.
void finish_volume(LoadedVolume& loaded, ScalarType type, const LoadOptions& options);

} // namespace snert::detail
