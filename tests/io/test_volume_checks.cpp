// Checks of loaded samples: the NaN / infinity policy (raw and through ITK), a label map's grid
// against its grey image's, the boundary iso of a label, and the histogram and Otsu threshold
// the iso suggestion starts from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "core/segmentation.h"
#include "core/volume_stats.h"
#include "io/load_volume.h"
#include "io/raw_volume.h"
#include "io/volume_checks.h"
#include "support/expect_error.h"
#include "support/real_data.h"
#include "support/temp_folder.h"
#include "volume_files.h"

namespace fs = std::filesystem;
using namespace snert;
using namespace snert::io_test;
using test::data_file;
using test::error_of;
using test::TempFolder;
using test::write_bytes;

TEST(NonFinite, ReplacedByTheFiniteRangeOrRefused) {
    TempFolder dir;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> values = {1, nan, 5, -inf, 3, inf, 2, 4};
    write_bytes(dir.file("f.raw"), as_bytes(values));
    RawOptions raw;
    raw.dims = {2, 2, 2};
    raw.type = ScalarType::Float32;
    const LoadedVolume lv = open_raw(dir.file("f.raw"), raw);
    EXPECT_EQ(lv.info.nonfinite, 3u);
    EXPECT_EQ(lv.volume.samples, (std::vector<float>{1, 1, 5, 1, 3, 5, 2, 4}));
    EXPECT_EQ(lv.info.range.min, 1.0f);
    EXPECT_EQ(lv.info.range.max, 5.0f);

    LoadOptions refuse;
    refuse.nonfinite = NonFinitePolicy::Refuse;
    expect_clear_error(error_of([&] { open_raw(dir.file("f.raw"), raw, refuse); }),
                       dir.file("f.raw"), "1 NaN and 2 infinite samples");

    write_bytes(dir.file("nan.raw"), as_bytes(std::vector<float>(8, nan)));
    expect_clear_error(error_of([&] { open_raw(dir.file("nan.raw"), raw); }), dir.file("nan.raw"),
                       "no finite sample");

    // The same policy through ITK (NRRD float).
    write_bytes(dir.file("f.nrrd"),
                concat(text_bytes(nrrd_header("float", "2 2 2", "raw")), as_bytes(values)));
    const LoadedVolume nrrd = open_volume(dir.file("f.nrrd"));
    EXPECT_EQ(nrrd.info.nonfinite, 3u);
    EXPECT_EQ(nrrd.volume.samples, lv.volume.samples);
}

TEST(LabelMaps, GridMismatchIsNamed) {
    SNERT_REQUIRE_DATA();
    const std::string ct = data_file("totalseg_ct_abdomen/example_ct_sm.nii.gz");
    const Volume grey = load_volume(ct);
    const Volume labels = load_volume(data_file("totalseg_ct_abdomen/example_seg.nii.gz"));
    EXPECT_NO_THROW(check_same_grid(grey, ct, labels, "seg"));
    TempFolder dir;
    write_bytes(dir.file("small.nrrd"),
                concat(text_bytes(nrrd_header("unsigned char", "10 10 10", "raw")), Bytes(1000)));
    const Volume small = load_volume(dir.file("small.nrrd"));
    const std::string message = error_of<std::invalid_argument>(
        [&] { check_same_grid(grey, ct, small, dir.file("small.nrrd")); });
    expect_clear_error(message, dir.file("small.nrrd"), "dimensions differ");
    EXPECT_NE(message.find("dims 10x10x10"), std::string::npos) << message;
    EXPECT_NE(message.find("dims 122x101x30"), std::string::npos) << message;
    Volume shifted = labels;
    shifted.origin.x += 1.5f; // half a voxel
    expect_clear_error(
        error_of<std::invalid_argument>([&] { check_same_grid(grey, ct, shifted, "shifted"); }),
        "shifted", "origin differ");
}

TEST(LabelMaps, BoundaryIsoOfTheLiver) {
    SNERT_REQUIRE_DATA();
    const Volume grey = load_volume(data_file("totalseg_ct_abdomen/example_ct_sm.nii.gz"));
    const Volume labels = load_volume(data_file("totalseg_ct_abdomen/example_seg.nii.gz"));
    const BoundaryIso b = boundary_iso(grey, segment_label(labels, 5));
    // Reference values computed independently from the files' bytes.
    EXPECT_EQ(b.pairs, 10095u);
    EXPECT_NEAR(b.inside_mean, 33.018227, 1e-4);
    EXPECT_NEAR(b.outside_mean, -25.927093, 1e-4);
    EXPECT_NEAR(b.iso, 3.545567f, 1e-4f);
    EXPECT_EQ(b.inside, InsideIs::Above);
}

TEST(LabelMaps, BoundaryIsoSynthetic) {
    Volume grey = make_volume({6, 6, 6}, 10.0f);
    Segmentation mask{grey.dims, std::vector<std::uint8_t>(grey.voxel_count(), 0)};
    for (int z = 2; z < 4; ++z)
        for (int y = 2; y < 4; ++y)
            for (int x = 2; x < 4; ++x) {
                mask.inside[mask.index(x, y, z)] = 1;
                grey.samples[grey.index(x, y, z)] = 90.0f;
            }
    BoundaryIso b = boundary_iso(grey, mask);
    EXPECT_EQ(b.pairs, 24u); // a 2x2x2 cube: 6 faces of 4 voxel pairs
    EXPECT_FLOAT_EQ(b.iso, 50.0f);
    EXPECT_EQ(b.inside, InsideIs::Above);
    for (auto& v : grey.samples) v = 100.0f - v; // dark object
    b = boundary_iso(grey, mask);
    EXPECT_FLOAT_EQ(b.iso, 50.0f);
    EXPECT_EQ(b.inside, InsideIs::Below);
    Segmentation empty{grey.dims, std::vector<std::uint8_t>(grey.voxel_count(), 0)};
    EXPECT_THROW(boundary_iso(grey, empty), std::invalid_argument);
}

TEST(Histogram, CountsAndTwoValuedOtsu) {
    Volume v = make_volume({10, 10, 10}, 20.0f);
    for (std::size_t i = 0; i < 300; ++i) v.samples[i] = 100.0f;
    v.samples[500] = std::numeric_limits<float>::quiet_NaN();
    const Histogram h = make_histogram(v, 16);
    EXPECT_EQ(h.lo, 20.0f);
    EXPECT_EQ(h.hi, 100.0f);
    EXPECT_EQ(h.total(), 999u); // the NaN is not counted
    EXPECT_EQ(h.counts.front(), 699u);
    EXPECT_EQ(h.counts.back(), 300u);
    EXPECT_DOUBLE_EQ(h.bin_width(), 5.0);
    // Two values: every split between them is equally good; Otsu takes the middle one.
    EXPECT_FLOAT_EQ(otsu_threshold(h), 60.0f);
    EXPECT_EQ(otsu_threshold(make_histogram(make_volume({2, 2, 2}, 7.0f))), 7.0f);
}

// A volume of several pieces (counted side by side on two threads): the counts one thread makes,
// and each bin's count as a bin-by-bin check of the formula gives it.
TEST(Histogram, TwoThreadsCountAsOne) {
    Volume v = make_volume({160, 160, 160}, 0.0f);
    for (std::size_t i = 0; i < v.samples.size(); ++i)
        v.samples[i] = float((i * 2654435761u) % 1000) * 0.25f - 30.0f;
    v.samples[12345] = std::numeric_limits<float>::infinity();
    std::vector<std::uint64_t> expected(256, 0);
    const ValueRange range = value_range(v);
    for (const float s : v.samples)
        if (std::isfinite(s))
            ++expected[std::min<std::size_t>(
                255, std::size_t((double(s) - double(range.min)) /
                                 (double(range.max) - double(range.min)) * 256.0))];
    for (const unsigned threads : {1u, 2u}) {
        const ThreadLimit limit(threads);
        const Histogram h = make_histogram(v, 256, range);
        EXPECT_EQ(h.counts, expected) << threads << " threads";
        EXPECT_EQ(h.total(), v.samples.size() - 1);
    }
}
