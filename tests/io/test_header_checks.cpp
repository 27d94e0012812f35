// snert's own header parsers and sample conversion (also fuzzed in tests/fuzz): every stored
// type widened in place in both byte orders, and parsers that refuse nonsense and report the
// sizes a header promises.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "io/metaimage.h"
#include "io/nifti.h"
#include "io/sample_conversion.h"
#include "io/sizes.h"
#include "io/vtk_legacy.h"
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

TEST(HeaderChecks, ConvertInPlaceEveryType) {
    const auto check = [](ScalarType type, auto sample_values) {
        using T = typename decltype(sample_values)::value_type;
        for (Endian endian : {Endian::Little, Endian::Big}) {
            std::vector<float> buffer(sample_values.size());
            auto* tail = static_cast<unsigned char*>(
                detail::stored_tail(buffer.data(), buffer.size(), type));
            for (std::size_t i = 0; i < sample_values.size(); ++i) {
                unsigned char b[sizeof(T)];
                std::memcpy(b, &sample_values[i], sizeof(T));
                if (endian != detail::native_endian()) std::reverse(b, b + sizeof(T));
                std::memcpy(tail + i * sizeof(T), b, sizeof(T));
            }
            detail::convert_in_place(buffer.data(), buffer.size(), type, endian);
            for (std::size_t i = 0; i < sample_values.size(); ++i)
                EXPECT_EQ(buffer[i], float(sample_values[i])) << scalar_type_name(type) << " " << i;
        }
    };
    // Long enough for the blocks of 16 and a tail after them: each sample's float lands where
    // it belongs, none overwritten before it is read.
    const auto check_long = [&](ScalarType type, auto sample_values) {
        auto repeated = sample_values;
        for (std::size_t i = 0; repeated.size() < 16 * 5 + 3; ++i)
            repeated.push_back(sample_values[(i * 7 + 3) % sample_values.size()]);
        check(type, repeated);
    };
    check(ScalarType::UInt8, std::vector<std::uint8_t>{0, 1, 127, 200, 255, 3, 4});
    check(ScalarType::Int8, std::vector<std::int8_t>{-128, -1, 0, 1, 127});
    check(ScalarType::UInt16, std::vector<std::uint16_t>{0, 1, 4095, 65535, 300});
    check(ScalarType::Int16, std::vector<std::int16_t>{-32768, -1024, 0, 1207, 32767});
    check(ScalarType::UInt32, std::vector<std::uint32_t>{0, 16777216, 7});
    check(ScalarType::Int32, std::vector<std::int32_t>{-16777216, 0, 5});
    check(ScalarType::Float32, std::vector<float>{-1.5f, 0.0f, 3.25e7f});
    check_long(ScalarType::UInt8, std::vector<std::uint8_t>{0, 1, 127, 200, 255, 3, 4});
    check_long(ScalarType::Int16, std::vector<std::int16_t>{-32768, -1024, 0, 1207, 32767});
    check_long(ScalarType::UInt16, std::vector<std::uint16_t>{0, 1, 4095, 65535, 300});
    check_long(ScalarType::Int32, std::vector<std::int32_t>{-16777216, 0, 5});
    std::vector<float> out(2);
    const double doubles[2] = {-2.5, 1e10};
    detail::convert_samples(doubles, 2, ScalarType::Float64, detail::native_endian(), out.data());
    EXPECT_EQ(out, (std::vector<float>{-2.5f, 1e10f}));
}

TEST(HeaderChecks, ParsersRejectNonsense) {
    const Bytes zeros(600);
    EXPECT_THROW(detail::parse_nifti_header(zeros.data(), zeros.size(), "z"), std::runtime_error);
    EXPECT_THROW(detail::parse_nifti_header(zeros.data(), 100, "z"), std::runtime_error);
    EXPECT_THROW(detail::parse_metaimage_header("NDims = 3\nDimSize = 2 2\n"
                                                "ElementDataFile = x\n",
                                                "m"),
                 std::runtime_error);
    const auto meta = detail::parse_metaimage_header(
        "NDims = 3\nDimSize = 4 5 6\nElementType = MET_SHORT\nElementDataFile = LOCAL\nXYZ", "m");
    EXPECT_EQ(meta.data_bytes(), 240u);
    EXPECT_EQ(meta.local_offset, 74u);
    const Bytes vtk =
        text_bytes("# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\n"
                   "DIMENSIONS 2 3 4\nPOINT_DATA 24\nSCALARS s short\n"
                   "LOOKUP_TABLE default\n");
    const auto h = detail::parse_vtk_header(vtk.data(), vtk.size(), "v");
    ASSERT_TRUE(h);
    EXPECT_EQ(h->data_bytes(), 48u);
    EXPECT_EQ(h->data_offset, vtk.size());
    EXPECT_EQ(detail::parse_meminfo_available("MemTotal: 10 kB\nMemAvailable:   2048 kB\n"),
              2048u * 1024u);
    EXPECT_EQ(detail::parse_meminfo_available("MemAvailable: lots\n"), 0u);
    EXPECT_THROW(detail::checked_dims("d", 0, 1, 1), std::runtime_error);
    EXPECT_EQ(detail::checked_dims("d", 2147483647, 1, 1), glm::ivec3(2147483647, 1, 1));
}
