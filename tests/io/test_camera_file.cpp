// Camera files for snert render --camera: the fields given, and one-line errors for bad ones.
#include <gtest/gtest.h>

#include "io/camera_file.h"
#include "support/expect_error.h"
#include "support/temp_folder.h"

using namespace snert;

TEST(CameraFile, ReadsTheFieldsGiven) {
    const test::TempFolder temp("snert-camera");
    test::write_text(temp.file("c.json"),
                     R"({"azimuth": 120, "roll": -5.5, "target": [1, 2.5, -3], "distance": 90})");
    const CameraSpec spec = read_camera_file(temp.file("c.json"));
    EXPECT_EQ(spec.azimuth, 120.0f);
    EXPECT_FALSE(spec.elevation); // left out: the framed camera's stays
    EXPECT_EQ(spec.roll, -5.5f);
    EXPECT_EQ(spec.target, glm::vec3(1.0f, 2.5f, -3.0f));
    EXPECT_EQ(spec.distance, 90.0f);
}

TEST(CameraFile, BadFilesSayWhatIsWrong) {
    const test::TempFolder temp("snert-camera-bad");
    auto expect = [&](const std::string& text, const std::string& message) {
        test::write_text(temp.file("bad.json"), text);
        test::expect_error<std::runtime_error>([&] { read_camera_file(temp.file("bad.json")); },
                                               {temp.file("bad.json"), message});
    };
    expect("{\"azimut\": 1}", "unknown key \"azimut\"");
    expect("[1, 2]", "not a JSON object");
    expect("{\"distance\": 0}", "\"distance\" must be greater than 0");
    expect("{\"target\": [1, 2]}", "\"target\" must be [x, y, z]");
    expect("{\"roll\": \"a\"}", "\"roll\" must be a finite number");
    EXPECT_THROW(read_camera_file(temp.file("missing.json")), std::runtime_error);
}
