// Window/level: how grey values become screen greys in the slice view, with the usual presets
// of radiology viewers, and the slice as RGBA pixels with the segmentation over it.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "names.h"
#include "slice.h"
#include "volume.h"

namespace snert {

struct WindowLevel {
    float window = 1.0f; // width of the value range mapped from black to white (> 0)
    float level = 0.5f;  // the value shown mid-grey
    bool operator==(const WindowLevel&) const = default;
};

enum class WindowPreset { Auto, Full, CtBone, CtSoftTissue, Mr };
// "auto", "full", "ct-bone", "ct-soft-tissue", "mr" (names.h helpers).
std::span<const Named<WindowPreset>> name_table(WindowPreset);

// CT bone W 2000 / L 400 and soft tissue W 400 / L 40 (Hounsfield units); MR and Full from the
// volume's values: MR the 1st to 99th percentile of the nonzero samples (an MR's background
// is 0 and a few bright voxels would grey out the rest), Full the whole range. Auto: soft
// tissue where the values look like Hounsfield units (air near -1000, bone above 200), MR
// where no value is negative, else the full range (a phantom's distance map).
WindowLevel window_preset(WindowPreset preset, const Volume& volume);

// 0..255 grey of a value: black below level - window / 2, white above level + window / 2.
std::uint8_t window_grey(float value, const WindowLevel& wl);

// The segmentation's colour in the slice view (a green no method colour is near).
inline constexpr glm::vec3 kSegmentationColour{0.3f, 0.85f, 0.35f};

// The slice as RGBA8 pixels (u fastest, v = 0 first), the mask (one per slice sample, may be
// empty) blended over the grey in `overlay` (RGB) with opacity `opacity`.
std::vector<std::uint8_t> slice_pixels(const Slice& slice, const WindowLevel& wl,
                                       std::span<const std::uint8_t> mask,
                                       glm::vec3 overlay = kSegmentationColour,
                                       float opacity = 0.35f);

} // namespace snert
