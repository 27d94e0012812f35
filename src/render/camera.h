// An orbit camera around a target point, with presets that frame a mesh's bounds.
//
// World axes follow the volumes (LPS for medical data): +z is up (superior), the front view
// looks from -y (anterior) towards +y, the side view from +x (the patient's left), the top
// view from +z down, and the iso view from the front-left-top octant. The camera is described
// by yaw (around +z, 0 = front) and pitch (elevation, +90 degrees = from above); its right
// vector depends on yaw only, so the top view is well defined.
#pragma once

#include <optional>
#include <span>
#include <string_view>

#include <glm/glm.hpp>

#include "core/camera_spec.h"
#include "core/mesh.h"
#include "core/names.h"

namespace snert::render {

enum class ViewPreset { Front, Side, Top, Iso };

// "front", "side", "top", "iso"; std::nullopt for anything else.
std::optional<ViewPreset> parse_view_preset(std::string_view name);
const char* view_preset_name(ViewPreset preset);
// The same names in the table of core/names.h (parse_name, name_of, name_choices).
std::span<const Named<ViewPreset>> name_table(ViewPreset);

struct OrbitCamera {
    glm::vec3 target{0.0f};
    float distance = 1.0f;             // eye to target (world units), > 0
    float yaw = 0.0f;                  // radians around +z; 0 looks from -y
    float pitch = 0.0f;                // radians, in [-pi/2, pi/2]
    float roll = 0.0f;                 // radians about the viewing direction (0: z stays up)
    float fov_y = glm::radians(30.0f); // vertical field of view; small to limit distortion
    float near_plane = 0.01f;          // world units, set by frame()
    float far_plane = 100.0f;

    // Unit vector from the target to the eye.
    glm::vec3 back() const;
    // Unit right and up vectors of the image plane (without roll, right depends on yaw only).
    glm::vec3 right() const;
    glm::vec3 up() const;
    glm::vec3 eye() const { return target + distance * back(); }

    glm::mat4 view() const;
    glm::mat4 projection(float aspect) const; // aspect = width / height

    // Interaction (the app): turn around the target, move closer (factor > 1) or farther,
    // and slide the target in the image plane by a fraction of the visible height.
    void orbit(float delta_yaw, float delta_pitch);
    void zoom(float factor);
    void pan(float right_fraction, float up_fraction);
};

// A camera looking from `preset` at `points` (a mesh's vertices), as close as possible while
// every point stays inside the image with `margin` (a fraction of the half-height or
// half-width) to spare, and centred on them in the image plane. Near and far planes enclose
// the points. aspect = width / height. Any number of points, none included.
OrbitCamera frame_points(std::span<const glm::vec3> points, ViewPreset preset, float aspect,
                         float margin = 0.06f);

// The same for the eight corners of a box.
OrbitCamera frame_bounds(const Bounds& bounds, ViewPreset preset, float aspect,
                         float margin = 0.06f);

// The camera with every field `spec` sets replaced (degrees to radians); the planes are
// re-fitted to `points` when anything changed.
void apply_camera_spec(OrbitCamera& camera, const CameraSpec& spec,
                       std::span<const glm::vec3> points);
// Every field of `camera` as a spec, and as `snert render` arguments: "--azimuth 45
// --elevation 35.26 --roll 0 --target 31.5,31.5,31.5 --distance 160.2".
CameraSpec camera_spec_of(const OrbitCamera& camera);
std::string camera_arguments(const CameraSpec& spec);

// Sets the near and far planes to enclose `points` seen from where the camera is (a camera
// given by hand: azimuth, elevation, target and distance).
void fit_planes(OrbitCamera& camera, std::span<const glm::vec3> points);

// Keeps the camera's direction and field of view; re-fits target, distance and planes.
void refit(OrbitCamera& camera, std::span<const glm::vec3> points, float aspect,
           float margin = 0.06f);

} // namespace snert::render
