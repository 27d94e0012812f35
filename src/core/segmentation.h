// Binary segmentation: which samples are inside the object. The surface net's topology comes
// from it; Marching Cubes uses the same rule on the grey values so both agree.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "volume.h"

namespace snert {

enum class InsideIs {
    Above, // inside where I >= iso (bright object: bone in CT, the phantoms)
    Below, // inside where I <= iso (dark object: air, CSF in T1)
};

inline bool is_inside(float value, float iso, InsideIs rule) {
    return rule == InsideIs::Above ? value >= iso : value <= iso;
}

struct Segmentation {
    glm::ivec3 dims{0};
    std::vector<std::uint8_t> inside; // 1 inside, 0 outside; same layout as Volume::samples

    std::size_t index(int x, int y, int z) const { return grid_index(dims, x, y, z); }
    bool at(int x, int y, int z) const { return inside[index(x, y, z)] != 0; }
    std::size_t count_inside() const;
};

// Thresholds the volume (in parallel over fixed chunks: parallel.h). NaN samples are outside.
Segmentation segment_threshold(const Volume& volume, float iso, InsideIs rule = InsideIs::Above);

// Inside where the label map equals `label` (a supervised segmentation).
Segmentation segment_label(const Volume& labels, int label);

// The segmentation as a 0/1 float volume with the geometry of `like` (for MC at 0.5 on a mask).
Volume mask_volume(const Segmentation& segmentation, const Volume& like);

} // namespace snert
