// Settings file and path completion: GL-free parts of the app.
#include <gtest/gtest.h>

#include <filesystem>

#include "app/path_completion.h"
#include "app/settings.h"
#include "core/names.h"
#include "support/temp_folder.h"

using namespace snert;
using namespace snert::app;
namespace fs = std::filesystem;

TEST(Settings, RoundTripsEveryField) {
    Settings s;
    s.parameters.close_border = false;
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
    s.view = {"smooth", true, 0.3f, "top", "radius-ratio"};
    s.layout.window_width = 1000;
    s.layout.bottom_tab = 1;
    s.play_speed = 25;
    s.parameters.volume.raw =
        RawOptions{{64, 48, 30}, ScalarType::Int16, {0.5f, 0.5f, 2.5f}, Endian::Big};
    s.parameters.volume.series_uid = "1.2.840.113619.2.1";
    s.parameters.volume.labels = "/data/head labels.nii.gz";
    s.parameters.volume.label = 7;
    s.parameters.volume.isotropic = 0.75f;
    SourceSpec labelled{"/a b/c.nii.gz"};
    labelled.labels = "/a b/seg.nii.gz";
    labelled.label = 5;
    SourceSpec raw{"/d.raw"};
    raw.raw = RawOptions{{10, 20, 30}, ScalarType::Float32, {1.0f, 1.0f, 1.5f}, Endian::Little};
    SourceSpec cubic{"/f.nrrd"};
    cubic.isotropic = 0.0f; // the smallest spacing
    s.recent_files = {labelled, raw, SourceSpec{"/e.mhd"}, cubic};
    s.iso_by_input[format_source_line(labelled)] = 190.5f;
    s.iso_by_input["/not/recent.nrrd"] = 7.0f; // only the recent inputs' are kept
    s.output_folder = "/a b/out";
    const std::string text = format_settings(s);
    EXPECT_NE(text.find("isotropic = 0.75\n"), std::string::npos) << text;
    EXPECT_NE(text.find("recent = /f.nrrd | isotropic=0\n"), std::string::npos) << text;
    EXPECT_NE(text.find("raw = 64,48,30\n"), std::string::npos) << text;
    EXPECT_NE(text.find("raw_type = int16\n"), std::string::npos) << text;
    EXPECT_NE(text.find("mode = sna\n"), std::string::npos) << text; // names, not labels
    EXPECT_NE(text.find("recent = /a b/c.nii.gz | labels=/a b/seg.nii.gz | label=5\n"),
              std::string::npos)
        << text;
    const Settings back = parse_settings(text);
    EXPECT_TRUE(back.parameters == s.parameters);
    EXPECT_TRUE(back.parameters.volume == s.parameters.volume);
    EXPECT_EQ(back.parameters.iso, 123.456f); // exactly: shortest round-trip text
    EXPECT_EQ(back.view.shading, "smooth");
    EXPECT_TRUE(back.view.wireframe);
    EXPECT_EQ(back.view.quality_threshold, 0.3f);
    EXPECT_EQ(back.view.preset, "top");
    EXPECT_EQ(back.view.color_by, "radius-ratio");
    EXPECT_EQ(back.layout.window_width, 1000);
    EXPECT_EQ(back.layout.bottom_tab, 1);
    EXPECT_EQ(back.play_speed, 25.0f);
    EXPECT_EQ(back.recent_files, s.recent_files);
    ASSERT_EQ(back.iso_by_input.size(), 1u);
    EXPECT_EQ(back.iso_by_input.at(format_source_line(labelled)), 190.5f);
    EXPECT_EQ(back.output_folder, "/a b/out");
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

// Every measure of core/names.h's table is a colour-by the settings keep, and only those.
TEST(Settings, ColourByTakesEveryMeasureName) {
    for (const Named<ShapeMeasure>& row : name_table(ShapeMeasure{})) {
        const Settings s = parse_settings("color_by = " + std::string(row.name) + "\n");
        EXPECT_EQ(s.view.color_by, row.name);
    }
    EXPECT_EQ(parse_settings("color_by = distance-iso\n").view.color_by, "distance-iso");
    EXPECT_EQ(parse_settings("color_by = distance\n").view.color_by, Settings().view.color_by);
}

TEST(Settings, AnInputWithoutOptionsWritesNoOptionKeys) {
    const std::string text = format_settings(Settings());
    for (const char* key : {"raw", "raw_type", "series", "labels", "label", "isotropic"})
        EXPECT_EQ(text.find(std::string("\n") + key + " ="), std::string::npos) << key;
    EXPECT_FALSE(parse_settings(text).parameters.volume.raw);
    // Raw options without their grid cannot be read, so they are dropped.
    EXPECT_FALSE(parse_settings("raw_type = uint16\n").parameters.volume.raw);
    EXPECT_FALSE(parse_settings("raw = 0,4,4\n").parameters.volume.raw);
}

TEST(Settings, SourceLinesReadBackAndRefuseBadOptions) {
    EXPECT_EQ(parse_source_line("/x/plain path.nrrd")->input, "/x/plain path.nrrd");
    const auto spec = parse_source_line("/x/q.1 | raw=64,64,93 | raw_type=uint16 | "
                                        "raw_spacing=3.2,3.2,1.5");
    ASSERT_TRUE(spec && spec->raw);
    EXPECT_EQ(spec->raw->dims, glm::ivec3(64, 64, 93));
    EXPECT_EQ(spec->raw->type, ScalarType::UInt16);
    EXPECT_EQ(spec->raw->spacing, glm::vec3(3.2f, 3.2f, 1.5f));
    EXPECT_EQ(spec->raw->endian, Endian::Little);
    EXPECT_EQ(format_source_line(*spec), "/x/q.1 | raw=64,64,93 | raw_type=uint16 | "
                                         "raw_spacing=3.2,3.2,1.5 | raw_endian=little");
    EXPECT_FALSE(parse_source_line(""));
    EXPECT_FALSE(parse_source_line("/x | label=five"));
    EXPECT_FALSE(parse_source_line("/x | isotropic=-1"));
    EXPECT_EQ(parse_source_line("/x | isotropic=1.5")->isotropic, 1.5f);
    EXPECT_FALSE(parse_source_line("/x | colour=red"));
    EXPECT_FALSE(parse_source_line("/x | raw_type=int16")); // no grid
    const Settings s = parse_settings("recent = /a.nrrd\nrecent = /b.raw | raw_type=nonsense\n"
                                      "recent = /a.nrrd\n");
    ASSERT_EQ(s.recent_files.size(), 1u); // the bad line and the repeat are skipped
    EXPECT_EQ(s.recent_files[0].input, "/a.nrrd");
}

TEST(Settings, RecentFilesAreUniqueNewestFirstAndBounded) {
    Settings s;
    auto file = [](int i) { return SourceSpec{"/f" + std::to_string(i)}; };
    for (int i = 0; i < 15; ++i) s.add_recent(file(i));
    s.add_recent(file(10));
    s.add_recent(SourceSpec{"phantom:sphere"}); // phantoms have their own menu
    ASSERT_EQ(s.recent_files.size(), Settings::kMaxRecent);
    EXPECT_EQ(s.recent_files[0], file(10));
    EXPECT_EQ(s.recent_files[1], file(14));
    EXPECT_EQ(std::count(s.recent_files.begin(), s.recent_files.end(), file(10)), 1);
    // The same file with another label is another input.
    SourceSpec labelled = file(14);
    labelled.labels = "/seg";
    labelled.label = 2;
    s.add_recent(labelled);
    EXPECT_EQ(s.recent_files[0], labelled);
    EXPECT_EQ(s.recent_files[1], file(10));
}

TEST(Settings, SavesAtomicallyAndLoadsMissingAsDefaults) {
    const test::TempFolder temp("snert-settings");
    const fs::path& folder = temp.path();
    const std::string path = (folder / "deep" / "settings.ini").string();
    EXPECT_TRUE(load_settings(path).parameters == Settings().parameters);
    Settings s;
    s.parameters.relax.max_iterations = 99;
    save_settings(s, path);
    EXPECT_EQ(load_settings(path).parameters.relax.max_iterations, 99);
    EXPECT_EQ(std::distance(fs::directory_iterator(folder / "deep"), fs::directory_iterator()), 1);
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
    const test::TempFolder temp("snert-completion");
    const fs::path& folder = temp.path();
    fs::create_directories(folder / "series1");
    fs::create_directories(folder / "series2");
    for (const char* name : {"head.nrrd", "heart.nii.gz", ".hidden"})
        test::write_text(folder / name, "x");
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
}

// Closing the border: absent from the file (the input's default: on for a label map) until
// chosen, then true or false.
TEST(Settings, CloseBorderDefaultsByInputUntilChosen) {
    Settings s;
    s.parameters.volume = {"/data/ct.nii.gz"};
    EXPECT_FALSE(s.parameters.request().close_border);
    EXPECT_EQ(format_settings(s).find("close_border"), std::string::npos);
    s.parameters.volume.labels = "/data/seg.nii.gz";
    s.parameters.volume.label = 5;
    EXPECT_TRUE(s.parameters.request().close_border);
    s.parameters.close_border = false;
    EXPECT_FALSE(s.parameters.request().close_border);
    const std::string text = format_settings(s);
    EXPECT_NE(text.find("close_border = false\n"), std::string::npos) << text;
    const Settings back = parse_settings(text);
    EXPECT_EQ(back.parameters.close_border, std::optional<bool>(false));
    EXPECT_FALSE(parse_settings("close_border = maybe\n").parameters.close_border);
}
