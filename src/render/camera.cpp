#include "camera.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace snert::render {

std::optional<ViewPreset> parse_view_preset(std::string_view name) {
    if (name == "front") return ViewPreset::Front;
    if (name == "side") return ViewPreset::Side;
    if (name == "top") return ViewPreset::Top;
    if (name == "iso") return ViewPreset::Iso;
    return std::nullopt;
}

namespace {
constexpr Named<ViewPreset> kViewPresets[] = {
    {ViewPreset::Front, "front", "front"},
    {ViewPreset::Side, "side", "side"},
    {ViewPreset::Top, "top", "top"},
    {ViewPreset::Iso, "iso", "iso"},
};
} // namespace

std::span<const Named<ViewPreset>> name_table(ViewPreset) {
    return kViewPresets;
}

const char* view_preset_name(ViewPreset preset) {
    switch (preset) {
    case ViewPreset::Front:
        return "front";
    case ViewPreset::Side:
        return "side";
    case ViewPreset::Top:
        return "top";
    case ViewPreset::Iso:
        return "iso";
    }
    return "?";
}

glm::vec3 OrbitCamera::back() const {
    return {std::sin(yaw) * std::cos(pitch), -std::cos(yaw) * std::cos(pitch), std::sin(pitch)};
}

glm::vec3 OrbitCamera::right() const {
    const glm::vec3 level(std::cos(yaw), std::sin(yaw), 0.0f);
    if (roll == 0.0f) return level;
    // Turned by roll about the viewing direction, within the image plane.
    const glm::vec3 level_up = glm::cross(back(), level);
    return std::cos(roll) * level + std::sin(roll) * level_up;
}

glm::vec3 OrbitCamera::up() const {
    return glm::cross(back(), right());
}

glm::mat4 OrbitCamera::view() const {
    // Rows of the rotation are the camera axes; the eye moves to the origin.
    const glm::vec3 r = right(), u = up(), b = back(), e = eye();
    glm::mat4 m(1.0f);
    for (int i = 0; i < 3; ++i) {
        m[i][0] = r[i];
        m[i][1] = u[i];
        m[i][2] = b[i];
    }
    m[3] = glm::vec4(-glm::dot(r, e), -glm::dot(u, e), -glm::dot(b, e), 1.0f);
    return m;
}

glm::mat4 OrbitCamera::projection(float aspect) const {
    return glm::perspective(fov_y, std::max(aspect, 1e-3f), near_plane, far_plane);
}

void OrbitCamera::orbit(float delta_yaw, float delta_pitch) {
    yaw = std::remainder(yaw + delta_yaw, 2.0f * glm::pi<float>());
    pitch = std::clamp(pitch + delta_pitch, -glm::half_pi<float>(), glm::half_pi<float>());
}

void OrbitCamera::zoom(float factor) {
    if (!(factor > 0.0f)) return;
    distance /= factor;
    // Keep the clipping planes around the target as it gets closer.
    near_plane = std::min(near_plane, distance * 0.01f);
}

void OrbitCamera::pan(float right_fraction, float up_fraction) {
    const float half_height = distance * std::tan(fov_y * 0.5f);
    target += (right_fraction * right() + up_fraction * up()) * (2.0f * half_height);
}

namespace {

void set_direction(OrbitCamera& camera, ViewPreset preset) {
    switch (preset) {
    case ViewPreset::Front:
        camera.yaw = 0.0f, camera.pitch = 0.0f;
        break;
    case ViewPreset::Side:
        camera.yaw = glm::half_pi<float>(), camera.pitch = 0.0f;
        break;
    case ViewPreset::Top:
        camera.yaw = 0.0f, camera.pitch = glm::half_pi<float>();
        break;
    case ViewPreset::Iso:
        // The direction (1, -1, 1): 45 degrees around z, atan(1/sqrt(2)) up.
        camera.yaw = glm::quarter_pi<float>();
        camera.pitch = std::atan(1.0f / std::sqrt(2.0f));
        break;
    }
}

} // namespace

void refit(OrbitCamera& camera, std::span<const glm::vec3> points, float aspect, float margin) {
    if (points.empty()) {
        const glm::vec3 origin(0.0f);
        refit(camera, std::span<const glm::vec3>(&origin, 1), aspect, margin);
        return;
    }
    glm::vec3 low = points.front(), high = points.front();
    for (const glm::vec3& p : points) {
        low = glm::min(low, p);
        high = glm::max(high, p);
    }
    const glm::vec3 r = camera.right(), u = camera.up(), b = camera.back();
    // Centre the points' extent in the image plane (exact for a parallel projection, close
    // for a narrow perspective one).
    const glm::vec3 centre = 0.5f * (low + high);
    glm::vec2 image_low(std::numeric_limits<float>::max()), image_high(-image_low);
    for (const glm::vec3& p : points) {
        const glm::vec2 xy(glm::dot(p - centre, r), glm::dot(p - centre, u));
        image_low = glm::min(image_low, xy);
        image_high = glm::max(image_high, xy);
    }
    const glm::vec2 shift = 0.5f * (image_low + image_high);
    const glm::vec3 target = centre + shift.x * r + shift.y * u;

    // A point at (x, y) in the image plane and z towards the eye is inside the frustum when
    // |x| <= (distance - z) tan_h and |y| <= (distance - z) tan_v.
    const float tan_v = std::tan(camera.fov_y * 0.5f) * (1.0f - margin);
    const float tan_h = tan_v * std::max(aspect, 1e-3f);
    float distance = 0.0f, radius = 0.0f;
    for (const glm::vec3& p : points) {
        const glm::vec3 d = p - target;
        const float z = glm::dot(d, b);
        distance = std::max(
            {distance, z + std::abs(glm::dot(d, r)) / tan_h, z + std::abs(glm::dot(d, u)) / tan_v});
        radius = std::max(radius, glm::length(d));
    }
    // A single point or a flat set seen edge-on still gets a usable camera.
    radius = std::max(radius, 1e-3f);
    camera.target = target;
    camera.distance = std::max(distance, 1.1f * radius); // the eye stays outside the points
    camera.near_plane = std::max(camera.distance - 1.05f * radius, camera.distance * 0.01f);
    camera.far_plane = camera.distance + 1.05f * radius;
}

void apply_camera_spec(OrbitCamera& camera, const CameraSpec& spec,
                       std::span<const glm::vec3> points) {
    if (!spec.any()) return;
    if (spec.azimuth) camera.yaw = glm::radians(*spec.azimuth);
    if (spec.elevation)
        camera.pitch = std::clamp(glm::radians(*spec.elevation), -glm::half_pi<float>(),
                                  glm::half_pi<float>());
    if (spec.roll) camera.roll = glm::radians(*spec.roll);
    if (spec.target) camera.target = *spec.target;
    if (spec.distance && *spec.distance > 0.0f) camera.distance = *spec.distance;
    fit_planes(camera, points);
}

CameraSpec camera_spec_of(const OrbitCamera& camera) {
    CameraSpec spec;
    spec.azimuth = glm::degrees(camera.yaw);
    spec.elevation = glm::degrees(camera.pitch);
    spec.roll = glm::degrees(camera.roll);
    spec.target = camera.target;
    spec.distance = camera.distance;
    return spec;
}

std::string camera_arguments(const CameraSpec& spec) {
    std::string out;
    char number[48];
    auto add = [&](const char* flag, const std::optional<float>& value) {
        if (!value) return;
        std::snprintf(number, sizeof number, "%.6g", double(*value));
        out += std::string(out.empty() ? "" : " ") + flag + " " + number;
    };
    add("--azimuth", spec.azimuth);
    add("--elevation", spec.elevation);
    add("--roll", spec.roll);
    if (spec.target) {
        std::snprintf(number, sizeof number, "%.6g,%.6g,%.6g", double(spec.target->x),
                      double(spec.target->y), double(spec.target->z));
        out += std::string(out.empty() ? "" : " ") + "--target " + number;
    }
    add("--distance", spec.distance);
    return out;
}

void fit_planes(OrbitCamera& camera, std::span<const glm::vec3> points) {
    const glm::vec3 eye = camera.eye(), b = camera.back();
    float nearest = std::numeric_limits<float>::max(), farthest = 0.0f;
    for (const glm::vec3& p : points) {
        const float depth = glm::dot(eye - p, b);
        nearest = std::min(nearest, depth);
        farthest = std::max(farthest, depth);
    }
    if (points.empty() || !(farthest > 0.0f)) farthest = 2.0f * camera.distance;
    const float slack = 0.05f * std::max(farthest - std::max(nearest, 0.0f), camera.distance);
    camera.far_plane = farthest + slack;
    camera.near_plane = std::max(nearest - slack, camera.far_plane * 1e-4f);
}

OrbitCamera frame_points(std::span<const glm::vec3> points, ViewPreset preset, float aspect,
                         float margin) {
    OrbitCamera camera;
    set_direction(camera, preset);
    refit(camera, points, aspect, margin);
    return camera;
}

OrbitCamera frame_bounds(const Bounds& bounds, ViewPreset preset, float aspect, float margin) {
    std::array<glm::vec3, 8> corners;
    for (int i = 0; i < 8; ++i)
        corners[std::size_t(i)] = {(i & 1) ? bounds.max.x : bounds.min.x,
                                   (i & 2) ? bounds.max.y : bounds.min.y,
                                   (i & 4) ? bounds.max.z : bounds.min.z};
    return frame_points(corners, preset, aspect, margin);
}

} // namespace snert::render
