// Settings file and path completion: GL-free parts of the app.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "app/path_completion.h"
#include "app/settings.h"

using namespace snert;
using namespace snert::app;
namespace fs = std::filesystem;

TEST(Settings, RoundTripsEveryField) {
    Settings s;
    s.parameters.volume = {"/data/head.nrrd", 96};
    s.parameters.auto_iso = false;
    s.parameters.iso = 123.456f;
    s.parameters.inside = InsideIs::Below;
    s.parameters.relax.mode = RelaxMode::Averaging;
    s.parameters.relax.smoothing_weight = 0.7f;
    s.parameters.relax.gradient_weight = 1.3f;
    s.parameters.relax.schedule = Schedule::SmoothingFirst;
    s.parameters.relax.favour_accuracy = false;
    s.parameters.relax.constraint = Constraint::Clip;
    s.parameters.relax.gradient = GradientMethod::Gaussian;
    s.parameters.relax.gradient_sigma = 1.7f;
    s.parameters.relax.max_iterations = 345;
    s.parameters.relax.epsilon = 3e-5f;
    s.parameters.triangulation = TriangulationRule::Delaunay;
    s.view = {"smooth", true, 0.3f, "top"};
    s.layout.window_width = 1000;
    s.layout.bottom_tab = 1;
    s.play_speed = 25;
    s.recent_files = {"/a b/c.nii.gz", "/d.mhd"};
    const Settings back = parse_settings(format_settings(s));
    EXPECT_TRUE(back.parameters == s.parameters);
    EXPECT_EQ(back.parameters.iso, 123.456f); // exactly: shortest round-trip text
    EXPECT_EQ(back.view.shading, "smooth");
    EXPECT_TRUE(back.view.wireframe);
    EXPECT_EQ(back.view.quality_threshold, 0.3f);
    EXPECT_EQ(back.view.preset, "top");
    EXPECT_EQ(back.layout.window_width, 1000);
    EXPECT_EQ(back.layout.bottom_tab, 1);
    EXPECT_EQ(back.play_speed, 25.0f);
    EXPECT_EQ(back.recent_files, s.recent_files);
}

TEST(Settings, SkipsBadValuesAndUnknownKeys) {
    const Settings s = parse_settings("mode = snert\nmode = nonsense\niterations = -5\n"
                                      "iterations=12\nshading = purple\nnot_a_key = 1\n"
                                      "epsilon = 1e-3abc\nsigma = inf\n# comment\n garbage line\n");
    EXPECT_EQ(s.parameters.relax.mode, RelaxMode::Snert);
    EXPECT_EQ(s.parameters.relax.max_iterations, 12);
    EXPECT_EQ(s.view.shading, Settings().view.shading);
    EXPECT_EQ(s.parameters.relax.epsilon, Settings().parameters.relax.epsilon);
    EXPECT_EQ(s.parameters.relax.gradient_sigma, Settings().parameters.relax.gradient_sigma);
}

TEST(Settings, RecentFilesAreUniqueNewestFirstAndBounded) {
    Settings s;
    for (int i = 0; i < 15; ++i) s.add_recent("/f" + std::to_string(i));
    s.add_recent("/f10");
    ASSERT_EQ(s.recent_files.size(), Settings::kMaxRecent);
    EXPECT_EQ(s.recent_files[0], "/f10");
    EXPECT_EQ(s.recent_files[1], "/f14");
    EXPECT_EQ(std::count(s.recent_files.begin(), s.recent_files.end(), "/f10"), 1);
}

TEST(Settings, SavesAtomicallyAndLoadsMissingAsDefaults) {
    const fs::path folder = fs::temp_directory_path() / "snert_settings_test";
    fs::remove_all(folder);
    const std::string path = (folder / "deep" / "settings.ini").string();
    EXPECT_TRUE(load_settings(path).parameters == Settings().parameters);
    Settings s;
    s.parameters.relax.max_iterations = 99;
    save_settings(s, path);
    EXPECT_EQ(load_settings(path).parameters.relax.max_iterations, 99);
    EXPECT_EQ(std::distance(fs::directory_iterator(folder / "deep"), fs::directory_iterator()), 1);
    fs::remove_all(folder);
}

TEST(Settings, DefaultPathFollowsXdg) {
    const char* old = std::getenv("XDG_CONFIG_HOME");
    const std::string saved = old ? old : "";
    setenv("XDG_CONFIG_HOME", "/tmp/xdg-test", 1);
    EXPECT_EQ(default_settings_path(), "/tmp/xdg-test/snert/settings.ini");
    if (old)
        setenv("XDG_CONFIG_HOME", saved.c_str(), 1);
    else
        unsetenv("XDG_CONFIG_HOME");
}

TEST(PathCompletion, CompletesAgainstExistingFiles) {
    const fs::path folder = fs::temp_directory_path() / "snert_completion_test";
    fs::remove_all(folder);
    fs::create_directories(folder / "series1");
    fs::create_directories(folder / "series2");
    std::ofstream(folder / "head.nrrd") << "x";
    std::ofstream(folder / "heart.nii.gz") << "x";
    std::ofstream(folder / ".hidden") << "x";
    const std::string base = folder.string() + "/";

    PathCompletion c = complete_path(base + "hea");
    EXPECT_EQ(c.completed, base + "hea"); // head / heart: nothing more in common
    EXPECT_EQ(c.candidates, (std::vector<std::string>{base + "head.nrrd", base + "heart.nii.gz"}));
    c = complete_path(base + "head");
    EXPECT_EQ(c.completed, base + "head.nrrd");
    c = complete_path(base + "s");
    EXPECT_EQ(c.completed, base + "series");
    EXPECT_EQ(c.candidates, (std::vector<std::string>{base + "series1/", base + "series2/"}));
    c = complete_path(base);
    EXPECT_EQ(c.candidates.size(), 4u); // folders first, no hidden file
    EXPECT_EQ(c.candidates[0], base + "series1/");
    c = complete_path(base + ".");
    EXPECT_EQ(c.candidates, (std::vector<std::string>{base + ".hidden"}));
    c = complete_path(base + "head", 0);
    EXPECT_TRUE(c.truncated);
    EXPECT_TRUE(complete_path("/no/such/folder/x").candidates.empty());
    EXPECT_TRUE(openable_path(base + "head.nrrd"));
    EXPECT_TRUE(openable_path(base + "series1"));
    EXPECT_FALSE(openable_path(base + "nothing"));
    fs::remove_all(folder);
}
