// The orbit camera: preset directions, an orthonormal frame, and framing that keeps every
// point inside the image with the requested margin while filling it.
#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>

#include "render/camera.h"

using namespace snert;
using namespace snert::render;

namespace {

// Largest |x| and |y| of the points in normalised device coordinates, and whether all lie
// between the near and far planes.
struct Extent {
    float x = 0, y = 0;
    bool inside_depth = true;
};
Extent ndc_extent(const OrbitCamera& camera, float aspect, const std::vector<glm::vec3>& points) {
    const glm::mat4 m = camera.projection(aspect) * camera.view();
    Extent e;
    for (const glm::vec3& p : points) {
        const glm::vec4 c = m * glm::vec4(p, 1.0f);
        e.x = std::max(e.x, std::abs(c.x / c.w));
        e.y = std::max(e.y, std::abs(c.y / c.w));
        if (c.w <= 0.0f || std::abs(c.z / c.w) > 1.0f) e.inside_depth = false;
    }
    return e;
}

std::vector<glm::vec3> corners(const Bounds& b) {
    std::vector<glm::vec3> c;
    for (int i = 0; i < 8; ++i)
        c.push_back({(i & 1) ? b.max.x : b.min.x, (i & 2) ? b.max.y : b.min.y,
                     (i & 4) ? b.max.z : b.min.z});
    return c;
}

// Points on a sphere, as a mesh's vertices would be.
std::vector<glm::vec3> sphere_points(glm::vec3 centre, float radius) {
    std::vector<glm::vec3> points;
    for (int i = 0; i <= 24; ++i)
        for (int j = 0; j < 48; ++j) {
            const float theta = glm::pi<float>() * float(i) / 24.0f;
            const float phi = 2.0f * glm::pi<float>() * float(j) / 48.0f;
            points.push_back(centre + radius * glm::vec3(std::sin(theta) * std::cos(phi),
                                                         std::sin(theta) * std::sin(phi),
                                                         std::cos(theta)));
        }
    return points;
}

void expect_near_vec(glm::vec3 a, glm::vec3 b) {
    EXPECT_NEAR(a.x, b.x, 1e-5f);
    EXPECT_NEAR(a.y, b.y, 1e-5f);
    EXPECT_NEAR(a.z, b.z, 1e-5f);
}

} // namespace

TEST(Camera, PresetNamesRoundTrip) {
    for (ViewPreset p : {ViewPreset::Front, ViewPreset::Side, ViewPreset::Top, ViewPreset::Iso})
        EXPECT_EQ(parse_view_preset(view_preset_name(p)), p);
    EXPECT_FALSE(parse_view_preset("back").has_value());
    EXPECT_FALSE(parse_view_preset("").has_value());
}

TEST(Camera, PresetsLookFromTheDocumentedDirections) {
    const Bounds box{glm::vec3(-1.0f), glm::vec3(1.0f)};
    // front: from -y with +z up and +x to the right; side: from +x; top: from +z.
    const OrbitCamera front = frame_bounds(box, ViewPreset::Front, 1.0f);
    expect_near_vec(front.back(), {0, -1, 0});
    expect_near_vec(front.up(), {0, 0, 1});
    expect_near_vec(front.right(), {1, 0, 0});
    expect_near_vec(frame_bounds(box, ViewPreset::Side, 1.0f).back(), {1, 0, 0});
    expect_near_vec(frame_bounds(box, ViewPreset::Side, 1.0f).up(), {0, 0, 1});
    expect_near_vec(frame_bounds(box, ViewPreset::Top, 1.0f).back(), {0, 0, 1});
    const float third = 1.0f / std::sqrt(3.0f);
    expect_near_vec(frame_bounds(box, ViewPreset::Iso, 1.0f).back(), {third, -third, third});
}

TEST(Camera, FrameIsOrthonormalAndRightHanded) {
    OrbitCamera camera;
    for (float yaw : {0.0f, 0.7f, -2.0f, 3.1f})
        for (float pitch : {-1.5707963f, -0.4f, 0.0f, 0.9f, 1.5707963f}) {
            camera.yaw = yaw, camera.pitch = pitch;
            const glm::vec3 r = camera.right(), u = camera.up(), b = camera.back();
            EXPECT_NEAR(glm::length(r), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::length(u), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::length(b), 1.0f, 1e-5f);
            EXPECT_NEAR(glm::dot(r, u), 0.0f, 1e-5f);
            EXPECT_NEAR(glm::dot(r, b), 0.0f, 1e-5f);
            expect_near_vec(glm::cross(r, u), b);
        }
}

TEST(Camera, ViewMatrixPutsTheEyeAtTheOriginLookingDownMinusZ) {
    OrbitCamera camera = frame_bounds({glm::vec3(2.0f), glm::vec3(6.0f)}, ViewPreset::Iso, 1.5f);
    const glm::mat4 view = camera.view();
    const glm::vec4 eye = view * glm::vec4(camera.eye(), 1.0f);
    expect_near_vec(glm::vec3(eye), {0, 0, 0});
    const glm::vec4 target = view * glm::vec4(camera.target, 1.0f);
    EXPECT_NEAR(target.x, 0.0f, 1e-4f);
    EXPECT_NEAR(target.y, 0.0f, 1e-4f);
    EXPECT_NEAR(target.z, -camera.distance, 1e-4f);
}

TEST(Camera, FramingKeepsEveryCornerInsideTheMarginAndFillsTheImage) {
    const Bounds box{glm::vec3(10.0f, -4.0f, 3.0f), glm::vec3(74.0f, 20.0f, 40.0f)};
    const float margin = 0.1f;
    for (ViewPreset preset :
         {ViewPreset::Front, ViewPreset::Side, ViewPreset::Top, ViewPreset::Iso})
        for (float aspect : {0.5f, 1.0f, 4.0f / 3.0f, 2.5f}) {
            const OrbitCamera camera = frame_bounds(box, preset, aspect, margin);
            const Extent e = ndc_extent(camera, aspect, corners(box));
            SCOPED_TRACE(std::string(view_preset_name(preset)) + " aspect " +
                         std::to_string(aspect));
            EXPECT_TRUE(e.inside_depth);
            EXPECT_LE(e.x, 1.0f - margin + 1e-4f);
            EXPECT_LE(e.y, 1.0f - margin + 1e-4f);
            // Tight: the binding axis reaches the margin.
            EXPECT_NEAR(std::max(e.x, e.y), 1.0f - margin, 2e-3f);
        }
}

TEST(Camera, FramingPointsCentresThemAndIsTighterThanTheirBox) {
    const std::vector<glm::vec3> points = sphere_points({30.0f, 12.0f, -5.0f}, 8.0f);
    const OrbitCamera by_points = frame_points(points, ViewPreset::Iso, 1.0f, 0.05f);
    Bounds box{points.front(), points.front()};
    for (const glm::vec3& p : points)
        box.min = glm::min(box.min, p), box.max = glm::max(box.max, p);
    const OrbitCamera by_box = frame_bounds(box, ViewPreset::Iso, 1.0f, 0.05f);
    EXPECT_LT(by_points.distance, 0.8f * by_box.distance);
    // The sphere's centre projects to the image centre.
    const glm::mat4 m = by_points.projection(1.0f) * by_points.view();
    const glm::vec4 c = m * glm::vec4(30.0f, 12.0f, -5.0f, 1.0f);
    EXPECT_NEAR(c.x / c.w, 0.0f, 1e-3f);
    EXPECT_NEAR(c.y / c.w, 0.0f, 1e-3f);
    const Extent e = ndc_extent(by_points, 1.0f, points);
    EXPECT_TRUE(e.inside_depth);
    EXPECT_LE(std::max(e.x, e.y), 0.95f + 1e-4f);
    EXPECT_GT(std::max(e.x, e.y), 0.93f);
}

TEST(Camera, DegenerateInputsStillGiveAUsableCamera) {
    for (const std::vector<glm::vec3>& points :
         {std::vector<glm::vec3>{}, std::vector<glm::vec3>{glm::vec3(5.0f)},
          std::vector<glm::vec3>{{0, 0, 0}, {10, 0, 0}}}) {
        const OrbitCamera camera = frame_points(points, ViewPreset::Front, 1.0f);
        EXPECT_GT(camera.distance, 0.0f);
        EXPECT_GT(camera.near_plane, 0.0f);
        EXPECT_GT(camera.far_plane, camera.near_plane);
        EXPECT_TRUE(std::isfinite(camera.view()[3][2]));
    }
}

TEST(Camera, ZoomOrbitAndPanMoveAsDocumented) {
    OrbitCamera camera = frame_bounds({glm::vec3(-1.0f), glm::vec3(1.0f)}, ViewPreset::Front, 1.0f);
    const float distance = camera.distance;
    camera.zoom(4.0f);
    EXPECT_NEAR(camera.distance, distance / 4.0f, 1e-5f);
    EXPECT_LE(camera.near_plane, camera.distance * 0.01f + 1e-6f);
    camera.orbit(0.0f, 10.0f); // clamped at the pole
    EXPECT_NEAR(camera.pitch, glm::half_pi<float>(), 1e-6f);
    const glm::vec3 before = camera.target;
    camera.pan(0.5f, 0.0f);
    // Half the visible height to the right.
    EXPECT_NEAR(glm::length(camera.target - before),
                camera.distance * std::tan(camera.fov_y * 0.5f), 1e-4f);
}

// A camera written as a spec (the app's View > Copy camera) and applied to another camera
// (snert render --azimuth ...) is the same camera; roll turns the image plane about the view.
TEST(Camera, SpecRoundTripsAndRollTurnsTheImagePlane) {
    OrbitCamera camera;
    camera.target = {3.0f, -2.0f, 7.5f};
    camera.distance = 42.0f;
    camera.yaw = 0.7f;
    camera.pitch = -0.3f;
    camera.roll = 0.25f;
    const CameraSpec spec = camera_spec_of(camera);
    const std::vector<glm::vec3> points = {{0, 0, 0}, {6, -4, 15}};
    OrbitCamera other = frame_points(points, ViewPreset::Front, 1.0f);
    apply_camera_spec(other, spec, points);
    EXPECT_NEAR(other.yaw, camera.yaw, 1e-6f);
    EXPECT_NEAR(other.pitch, camera.pitch, 1e-6f);
    EXPECT_NEAR(other.roll, camera.roll, 1e-6f);
    EXPECT_EQ(other.target, camera.target);
    EXPECT_EQ(other.distance, camera.distance);
    // The planes enclose the points seen from there.
    for (const glm::vec3& p : points) {
        const float depth = glm::dot(other.eye() - p, other.back());
        EXPECT_GT(depth, other.near_plane);
        EXPECT_LT(depth, other.far_plane);
    }
    EXPECT_EQ(camera_arguments(CameraSpec{45.0f, 35.26f, 0.0f, glm::vec3(1.5f, 2, 3), 160.25f}),
              "--azimuth 45 --elevation 35.26 --roll 0 --target 1.5,2,3 --distance 160.25");

    // Roll: right and up turn about back() by the angle, and stay orthonormal.
    OrbitCamera level = camera;
    level.roll = 0.0f;
    EXPECT_NEAR(glm::dot(camera.right(), level.right()), std::cos(0.25f), 1e-6f);
    EXPECT_NEAR(glm::dot(camera.right(), level.up()), std::sin(0.25f), 1e-6f);
    EXPECT_NEAR(glm::dot(camera.right(), camera.back()), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(camera.up(), camera.right()), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(camera.up()), 1.0f, 1e-6f);
}
