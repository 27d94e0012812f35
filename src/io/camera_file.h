// A camera saved as JSON for `snert render --camera FILE.json`: any of
//   {"azimuth": 45, "elevation": 35.26, "roll": 0, "target": [31.5, 31.5, 31.5],
//    "distance": 160.2}
// (degrees, world millimetres; core/camera_spec.h). Fields left out keep the framed camera's.
#pragma once

#include <string>

#include "core/camera_spec.h"

namespace snert {

// Throws std::runtime_error naming the file: missing, over 64 KiB, not JSON, an unknown key,
// a value that is not a finite number (target: three of them), a distance that is not > 0.
CameraSpec read_camera_file(const std::string& path);

} // namespace snert
