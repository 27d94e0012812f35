// Checks of freshly read samples (no ITK): the NaN / infinity policy every reader applies, and
// a label map's grid against its grey image's.
#pragma once

#include <cstddef>
#include <string>

#include "core/volume.h"

namespace snert {

// ---- NaN / infinity policy -----------------------------------------------------------------
//
// Float data only; integer types cannot hold them. See load_volume.h's top for what a load
// reports.

enum class NonFinitePolicy {
    Replace, // NaN, -inf -> smallest finite sample; +inf -> largest finite sample (default)
    Refuse,  // any NaN or inf fails the load
};

struct NonFiniteCount {
    std::size_t nan = 0, positive_infinity = 0, negative_infinity = 0;
    std::size_t total() const { return nan + positive_infinity + negative_infinity; }
};
// Applies the policy to the samples; `name` starts the error message. Replace: every NaN and
// -inf becomes the smallest finite sample, every +inf the largest, so no NaN reaches a mesh, a
// gradient or a metric; a volume with no finite sample at all is refused. Refuse: any
// non-finite sample fails, the message saying how many NaN and infinite samples there are.
// Both throw std::runtime_error. Returns what was found (and, for Replace, replaced).
NonFiniteCount apply_nonfinite_policy(Volume& volume, NonFinitePolicy policy,
                                      const std::string& name);

// ---- Label maps beside a grey image ----------------------------------------------------------

// Throws std::invalid_argument when the two volumes do not share one grid: same dims, spacing
// and origin equal within 1e-3 of the smallest voxel size, direction columns within 1e-3. The
// message names both files, says what differs and gives both grids.
void check_same_grid(const Volume& grey, const std::string& grey_name, const Volume& labels,
                     const std::string& labels_name);

} // namespace snert
