#include "camera_file.h"

#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "file_bytes.h"

namespace snert {

namespace {
constexpr std::uint64_t kMaxCameraFileBytes = 64 * 1024;
} // namespace

CameraSpec read_camera_file(const std::string& path) {
    if (detail::file_size(path) > kMaxCameraFileBytes)
        throw std::runtime_error(path + ": too large for a camera file (over 64 KiB)");
    const std::vector<std::uint8_t> bytes = detail::read_file_prefix(path, kMaxCameraFileBytes);
    const nlohmann::json json = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
    if (json.is_discarded() || !json.is_object())
        throw std::runtime_error(path + ": not a JSON object");
    auto number = [&](const nlohmann::json& value, const std::string& key) {
        if (!value.is_number() || !std::isfinite(value.get<double>()))
            throw std::runtime_error(path + ": \"" + key + "\" must be a finite number");
        return value.get<float>();
    };
    CameraSpec spec;
    for (const auto& [key, value] : json.items()) {
        if (key == "azimuth") {
            spec.azimuth = number(value, key);
        } else if (key == "elevation") {
            spec.elevation = number(value, key);
        } else if (key == "roll") {
            spec.roll = number(value, key);
        } else if (key == "distance") {
            spec.distance = number(value, key);
            if (!(*spec.distance > 0.0f))
                throw std::runtime_error(path + ": \"distance\" must be greater than 0");
        } else if (key == "target") {
            if (!value.is_array() || value.size() != 3)
                throw std::runtime_error(path + ": \"target\" must be [x, y, z]");
            spec.target =
                glm::vec3(number(value[0], key), number(value[1], key), number(value[2], key));
        } else {
            throw std::runtime_error(path + ": unknown key \"" + key +
                                     "\" (azimuth, elevation, roll, target, distance)");
        }
    }
    return spec;
}

} // namespace snert
