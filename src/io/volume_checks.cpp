// Checks of freshly read samples: the NaN / infinity policy, and a label map's grid against
// its grey image's.
#include "volume_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace snert {

// ---- NaN / infinity policy -----------------------------------------------------------------

NonFiniteCount apply_nonfinite_policy(Volume& volume, NonFinitePolicy policy,
                                      const std::string& name) {
    NonFiniteCount count;
    for (float v : volume.samples) {
        if (std::isnan(v))
            ++count.nan;
        else if (std::isinf(v))
            ++(v > 0 ? count.positive_infinity : count.negative_infinity);
    }
    if (count.total() == 0) return count;
    const std::string found = std::to_string(count.nan) + " NaN and " +
                              std::to_string(count.positive_infinity + count.negative_infinity) +
                              " infinite samples";
    if (policy == NonFinitePolicy::Refuse)
        throw std::runtime_error(name + ": " + found + " (non-finite samples are refused)");
    if (count.total() == volume.samples.size())
        throw std::runtime_error(name + ": no finite sample (" + found + ")");
    const ValueRange range = value_range(volume);
    for (float& v : volume.samples) {
        if (std::isnan(v) || v == -std::numeric_limits<float>::infinity())
            v = range.min;
        else if (v == std::numeric_limits<float>::infinity())
            v = range.max;
    }
    return count;
}

// ---- Label maps ---------------------------------------------------------------------------------

namespace {

std::string text(glm::ivec3 v) {
    return std::to_string(v.x) + "x" + std::to_string(v.y) + "x" + std::to_string(v.z);
}

std::string text(glm::vec3 v) {
    std::ostringstream out;
    out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return out.str();
}

std::string grid_text(const Volume& v) {
    return "dims " + text(v.dims) + ", spacing " + text(v.spacing) + ", origin " + text(v.origin);
}

} // namespace

void check_same_grid(const Volume& grey, const std::string& grey_name, const Volume& labels,
                     const std::string& labels_name) {
    const float voxel = std::min({grey.spacing.x, grey.spacing.y, grey.spacing.z});
    const float tolerance = 1e-3f * std::max(voxel, 1e-6f);
    std::string what;
    if (grey.dims != labels.dims) {
        what = "dimensions";
    } else if (glm::any(glm::greaterThan(glm::abs(grey.spacing - labels.spacing),
                                         glm::vec3(tolerance)))) {
        what = "spacing";
    } else if (glm::length(grey.origin - labels.origin) > tolerance) {
        what = "origin";
    } else {
        for (int c = 0; c < 3; ++c)
            if (glm::length(grey.direction[c] - labels.direction[c]) > 1e-3f) what = "direction";
    }
    if (what.empty()) return;
    throw std::invalid_argument(labels_name + ": the label map's grid does not match " + grey_name +
                                " (" + what + " differ): labels have " + grid_text(labels) +
                                "; the grey image has " + grid_text(grey));
}

} // namespace snert
