// Headerless raw volumes: one file, or a numbered series of slice files (no ITK).
//
// Nothing in a raw file says what it holds: the caller gives the dimensions, the sample type,
// the byte order and the spacing, and the file sizes are the only check there is. Samples are
// converted to float32 as for every format (load_volume.h), with origin 0 and identity
// direction, and float data passes the NaN / infinity policy of LoadOptions.
#pragma once

#include <string>

#include <glm/glm.hpp>

#include "core/volume.h"
#include "load_volume.h"
#include "sample_conversion.h"

namespace snert {

// Headerless raw samples: one file of dims.x*dims.y*dims.z samples (its size must match
// exactly), or a numbered series of slice files, each dims.x*dims.y samples. A series is
// recognised when `path` names a file of exactly one slice whose name holds a number
// (quarter.1, IM-0001.raw): the following slices are the same name with the number counting
// up (quarter.2 ... quarter.93; zero padding, as in 0001, is kept).
struct RawOptions {
    glm::ivec3 dims{0}; // samples along x, y, z (each >= 1)
    ScalarType type = ScalarType::UInt8;
    glm::vec3 spacing{1.0f};        // millimetres, each > 0
    Endian endian = Endian::Little; // byte order of multi-byte samples

    bool operator==(const RawOptions&) const = default;
};

// Loads headerless raw data (one file or a numbered slice series, see RawOptions). Throws
// std::invalid_argument for bad options (dims below 1, spacing not positive and finite) and
// std::runtime_error, naming the sizes, for a file or series that does not hold exactly the
// samples described; both before the grid is allocated.
LoadedVolume open_raw(const std::string& path, const RawOptions& raw,
                      const LoadOptions& options = {});
Volume load_raw(const std::string& path, const RawOptions& raw, const LoadOptions& options = {});

} // namespace snert
