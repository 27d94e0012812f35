// A camera as people give it to `snert render` (--azimuth --elevation --roll --target
// --distance, or --camera FILE.json) and as the app's View menu copies it: degrees and world
// millimetres. Each field that is set replaces the one of the camera framed on the meshes.
#pragma once

#include <optional>

#include <glm/glm.hpp>

namespace snert {

struct CameraSpec {
    std::optional<float> azimuth;   // degrees around +z; 0 looks from -y (front)
    std::optional<float> elevation; // degrees above the xy plane, in [-90, 90]
    std::optional<float> roll;      // degrees about the viewing direction
    std::optional<glm::vec3> target;
    std::optional<float> distance; // eye to target, > 0

    bool any() const { return azimuth || elevation || roll || target || distance; }
};

} // namespace snert
