// The app opens whatever the CLI opens: for each kind of input, the spec that the command
// line's options parse to (src/cli/options.h, as `snert compare` and `snert gui` take them)
// equals the one the app's Open panel builds from the same choices, and the app opens it,
// both from its panel and when `snert gui` hands it over (AppOptions::source).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/headless.h"
#include "cli/options.h"
#include "support/real_data.h"
#include "support/temp_folder.h"

using namespace snert;
using namespace snert::app;

namespace {

namespace fs = std::filesystem;

// The spec the CLI's input options give for `args` (the words after the subcommand).
SourceSpec cli_spec(const std::vector<std::string>& args) {
    CLI::App command("parity");
    cli::InputArgs input;
    cli::add_input_options(command, input);
    std::vector<std::string> reversed(args.rbegin(), args.rend()); // CLI11 takes them reversed
    command.parse(reversed);
    return cli::input_choice(input).spec;
}

bool settled(const App& app) {
    const JobResults& r = app.results();
    return r.finished && r.mc && r.frame && r.mc_current && r.frame_current &&
           r.frame->metrics_complete;
}

bool loaded(const App& app, const SourceSpec& spec) {
    return settled(app) && app.loaded_source() && *app.loaded_source() == spec &&
           app.results().source && app.results().source->spec == spec;
}

HeadlessOptions options_for(const SourceSpec& spec) {
    HeadlessOptions options;
    options.width = 1100;
    options.height = 720;
    options.gl_backend = "osmesa";
    options.app.source = spec;
    PipelineOptions pipeline;
    pipeline.relax.max_iterations = 0; // the input is the point: MC and the initial net

    options.app.pipeline = pipeline;
    return options;
}

// `snert gui ARGS`: the app starts on the CLI's spec and opens it.
void expect_gui_opens(const SourceSpec& spec) {
    HeadlessApp h(options_for(spec));
    ASSERT_TRUE(h.run_until([&](const App& a) { return loaded(a, spec); }, 300))
        << format_source_line(spec) << ": " << h.app().load_error();
    EXPECT_TRUE(h.app().load_error().empty());
}

// The app, on a small phantom, opening `spec` from its panel with `use_panel`; the result is
// compared with the CLI's and opened.
template <class UsePanel> void expect_panel_opens(const SourceSpec& cli, UsePanel use_panel) {
    HeadlessApp h(options_for({"phantom:sphere", 20}));
    App& app = h.app();
    ASSERT_TRUE(h.run_until([](const App& a) { return settled(a); }));
    use_panel(h);
    EXPECT_EQ(format_source_line(app.settings().parameters.volume), format_source_line(cli));
    EXPECT_EQ(app.settings().parameters.volume, cli);
    ASSERT_TRUE(h.run_until([&](const App& a) { return loaded(a, cli); }, 300))
        << format_source_line(cli) << ": " << app.load_error();
}

// A small uint16 big-endian raw file: a bright box in a dark one.
std::string write_raw(const test::TempFolder& folder) {
    std::vector<std::uint8_t> bytes;
    for (int z = 0; z < 12; ++z)
        for (int y = 0; y < 11; ++y)
            for (int x = 0; x < 10; ++x) {
                const bool in = x > 2 && x < 7 && y > 2 && y < 8 && z > 3 && z < 9;
                const std::uint16_t v = in ? 3000 : 100;
                bytes.push_back(std::uint8_t(v >> 8));
                bytes.push_back(std::uint8_t(v & 0xff));
            }
    const std::string path = folder.file("box.raw");
    test::write_bytes(path, bytes);
    return path;
}

} // namespace

TEST(InputParity, Phantom) {
    const SourceSpec cli = cli_spec({"phantom:torus", "--size", "24"});
    EXPECT_EQ(cli, (SourceSpec{"phantom:torus", 24}));
    HeadlessApp h(options_for({"phantom:sphere", 24}));
    App& app = h.app();
    app.form().path = "phantom:torus"; // typed into the path field
    app.open_form();
    EXPECT_EQ(app.settings().parameters.volume, cli);
    ASSERT_TRUE(h.run_until([&](const App& a) { return loaded(a, cli); }));
    expect_gui_opens(cli);
}

TEST(InputParity, NrrdFile) {
    const test::TempFolder temp("snert-parity-nrrd");
    const std::string path = temp.file("box.nrrd");
    std::string text = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 10 11 12\nencoding: raw\n\n";
    for (int i = 0; i < 10 * 11 * 12; ++i) text += char((i / 10) % 11 > 5 ? 200 : 10);
    test::write_text(path, text);
    const SourceSpec cli = cli_spec({path});
    expect_panel_opens(cli, [&](HeadlessApp& h) {
        h.app().form().path = path;
        h.app().open_form();
    });
    expect_gui_opens(cli);
}

// Cubic voxels: the Volume panel's switch and edge are the CLI's --isotropic MM.
TEST(InputParity, CubicVoxels) {
    const test::TempFolder temp("snert-parity-cubic");
    const std::string path = write_raw(temp);
    const SourceSpec cli =
        cli_spec({path, "--raw", "10,11,12", "--raw-type", "uint16", "--raw-spacing",
                  "0.5,0.5,1.25", "--raw-endian", "big", "--isotropic", "0.4"});
    ASSERT_EQ(cli.isotropic, 0.4f);
    EXPECT_EQ(cli_spec({path, "--isotropic"}).isotropic, 0.0f); // the smallest spacing
    expect_panel_opens(cli, [&](HeadlessApp& h) {
        OpenForm& form = h.app().form();
        form.path = path;
        form.raw = true;
        form.raw_options = {{10, 11, 12}, ScalarType::UInt16, {0.5f, 0.5f, 1.25f}, Endian::Big};
        form.cubic = true;
        form.cubic_edge = 0.4f;
        h.app().open_form();
    });
    expect_gui_opens(cli);
}

TEST(InputParity, HeaderlessRaw) {
    const test::TempFolder temp("snert-parity-raw");
    const std::string path = write_raw(temp);
    const SourceSpec cli = cli_spec({path, "--raw", "10,11,12", "--raw-type", "uint16",
                                     "--raw-spacing", "0.5,0.5,1.25", "--raw-endian", "big"});
    ASSERT_TRUE(cli.raw);
    expect_panel_opens(cli, [&](HeadlessApp& h) {
        OpenForm& form = h.app().form();
        form.path = path;
        form.raw = true;
        form.raw_options = {{10, 11, 12}, ScalarType::UInt16, {0.5f, 0.5f, 1.25f}, Endian::Big};
        h.app().open_form();
    });
    expect_gui_opens(cli);
}

TEST(InputParity, RawSliceSeries) {
    SNERT_REQUIRE_DATA();
    const std::string first = test::data_file("headsq/quarter.1");
    if (!fs::exists(first)) GTEST_SKIP() << "no " << first;
    // As tests/cli/cli_test.sh exports it.
    const SourceSpec cli = cli_spec(
        {first, "--raw", "64,64,93", "--raw-type", "uint16", "--raw-spacing", "3.2,3.2,1.5"});
    expect_panel_opens(cli, [&](HeadlessApp& h) {
        OpenForm& form = h.app().form();
        form.path = first;
        form.raw = true;
        form.raw_options = {{64, 64, 93}, ScalarType::UInt16, {3.2f, 3.2f, 1.5f}, Endian::Little};
        h.app().open_form();
    });
}

TEST(InputParity, LabelMapAndLabel) {
    SNERT_REQUIRE_DATA();
    const std::string ct = test::data_file("totalseg_ct_abdomen/example_ct_sm.nii.gz");
    const std::string seg = test::data_file("totalseg_ct_abdomen/example_seg.nii.gz");
    if (!fs::exists(ct) || !fs::exists(seg)) GTEST_SKIP() << "no TotalSegmentator example";
    // As tests/cli/cli_test.sh compares it.
    const SourceSpec cli = cli_spec({ct, "--labels", seg, "--label", "5"});
    expect_panel_opens(cli, [&](HeadlessApp& h) {
        App& app = h.app();
        app.form().path = ct;
        app.form().labels = seg;
        app.open_form(); // lists the labels
        SourceSpec listed{ct};
        listed.labels = seg;
        ASSERT_TRUE(h.run_until([&](const App& a) { return loaded(a, listed); }, 300));
        app.choose_label(5);
    });
    expect_gui_opens(cli);
}

TEST(InputParity, DicomFolderAndSeries) {
    SNERT_REQUIRE_DATA();
    if (SNERT_LARGE_VOLUMES == 0)
        GTEST_SKIP() << "the DICOM head (770 k triangles, meshed twice) takes minutes under the "
                        "sanitizers; this test runs in optimized builds";
    const std::string folder = test::data_file("dicom_mr_head_t1_sag");
    if (!fs::is_directory(folder)) GTEST_SKIP() << "no " << folder;
    HeadlessApp h(options_for({"phantom:sphere", 20}));
    App& app = h.app();
    ASSERT_TRUE(h.run_until([](const App& a) { return settled(a); }));
    // The folder: its largest series.
    const SourceSpec largest = cli_spec({folder});
    app.open_path(folder);
    EXPECT_EQ(app.settings().parameters.volume, largest);
    ASSERT_TRUE(h.run_until(
        [&](const App& a) { return loaded(a, largest) && !a.series_list().scanning; }, 300));
    ASSERT_FALSE(app.series_list().series.empty()) << app.series_list().error;
    // One series of it, by its UID.
    const std::string uid = app.series_list().series.front().uid;
    const SourceSpec cli = cli_spec({folder, "--series", uid});
    app.choose_series(uid);
    EXPECT_EQ(app.settings().parameters.volume, cli);
    ASSERT_TRUE(h.run_until([&](const App& a) { return loaded(a, cli); }, 300)) << app.load_error();
}
