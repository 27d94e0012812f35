// Headerless raw data: the headsq slice series from the shared test data, the same samples as
// one file and byte-swapped, zero-padded float64 series, and the numbered names a series is
// counted from.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <utility>

#include "io/numbered_series.h"
#include "io/raw_volume.h"
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

TEST(LoadVolume, RawSliceSeriesHeadsq) {
    SNERT_REQUIRE_DATA();
    RawOptions raw;
    raw.dims = {64, 64, 93};
    raw.type = ScalarType::UInt16;
    raw.spacing = {3.2f, 3.2f, 1.5f};
    const LoadedVolume lv = open_raw(data_file("headsq/quarter.1"), raw);
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "raw");
    EXPECT_EQ(lv.info.files, 93u);
    EXPECT_EQ(v.dims, glm::ivec3(64, 64, 93));
    expect_vec3_near(v.spacing, {3.2f, 3.2f, 1.5f}, 0.0f);
    EXPECT_EQ(v.at(32, 32, 46), 122.0f);
    EXPECT_EQ(v.at(21, 42, 23), 1075.0f);
    EXPECT_EQ(v.at(39, 24, 53), 3926.0f);
    EXPECT_EQ(sum_of(v), 193392317.0);
    EXPECT_EQ(lv.info.range.min, 0.0f);
    EXPECT_EQ(lv.info.range.max, 3926.0f);
}

TEST(LoadVolume, RawSingleFileAndBigEndianMatchTheSeries) {
    SNERT_REQUIRE_DATA();
    RawOptions raw;
    raw.dims = {64, 64, 93};
    raw.type = ScalarType::UInt16;
    const Volume series = load_raw(data_file("headsq/quarter.1"), raw);
    Bytes little, big;
    for (int k = 1; k <= 93; ++k)
        little = concat(little, read_bytes(data_file("headsq/quarter." + std::to_string(k))));
    big = little;
    for (std::size_t i = 0; i + 1 < big.size(); i += 2) std::swap(big[i], big[i + 1]);
    TempFolder dir;
    write_bytes(dir.file("head.raw"), little);
    write_bytes(dir.file("head_be.raw"), big);
    EXPECT_EQ(load_raw(dir.file("head.raw"), raw).samples, series.samples);
    raw.endian = Endian::Big;
    EXPECT_EQ(load_raw(dir.file("head_be.raw"), raw).samples, series.samples);
}

TEST(LoadVolume, RawZeroPaddedSeriesAndFloat64) {
    TempFolder dir;
    // Three slices of 2x2 float64, big-endian, named s001.f64 .. s003.f64.
    for (int k = 1; k <= 3; ++k) {
        Bytes slice;
        for (int i = 0; i < 4; ++i) {
            const double value = k * 10.0 + i + 0.5;
            std::uint8_t b[8];
            std::memcpy(b, &value, 8);
            for (int j = 7; j >= 0; --j) slice.push_back(b[j]);
        }
        write_bytes(dir.file("s00" + std::to_string(k) + ".f64"), slice);
    }
    RawOptions raw;
    raw.dims = {2, 2, 3};
    raw.type = ScalarType::Float64;
    raw.endian = Endian::Big;
    const Volume v = load_raw(dir.file("s001.f64"), raw);
    EXPECT_EQ(v.at(0, 0, 0), 10.5f);
    EXPECT_EQ(v.at(1, 1, 2), 33.5f);
    EXPECT_EQ(v.at(1, 0, 1), 21.5f);
}

TEST(HeaderChecks, NumberedNames) {
    auto n = detail::parse_numbered_name("dir9/quarter.1");
    ASSERT_TRUE(n);
    EXPECT_EQ(detail::numbered_path(*n, 93), "dir9/quarter.93");
    n = detail::parse_numbered_name("IM-0009.raw");
    ASSERT_TRUE(n);
    EXPECT_EQ(n->width, 4u);
    EXPECT_EQ(detail::numbered_path(*n, 10), "IM-0010.raw");
    EXPECT_FALSE(detail::parse_numbered_name("dir9/slices"));
    n = detail::parse_numbered_name("s001.f64"); // the number before the extension first
    ASSERT_TRUE(n);
    EXPECT_EQ(detail::numbered_path(*n, 2), "s002.f64");
    EXPECT_EQ(detail::numbered_name_candidates("head5.1").size(), 2u);
}
