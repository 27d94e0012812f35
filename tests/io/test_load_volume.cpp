// Loading volume files through open_volume: NRRD, MetaImage and VTK from the shared test data
// (values checked against numbers decoded independently from the files' bytes and against the
// data's SOURCES.md), and bad files of any format that must fail with a clear one-line error
// and no crash: missing, empty, unknown, truncated, lying, absurd, too large, unsupported.
// NIfTI, DICOM and raw data have their own files.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/volume_stats.h"
#include "io/load_volume.h"
#include "io/raw_volume.h"
#include "io/sample_conversion.h"
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

TEST(LoadVolume, NrrdFlairKeepsObliqueGeometry) {
    SNERT_REQUIRE_DATA();
    const LoadedVolume lv = open_volume(data_file("FLAIR.nrrd"));
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "NRRD");
    EXPECT_EQ(lv.info.scalar_type, "uint8");
    EXPECT_EQ(v.dims, glm::ivec3(124, 160, 140));
    expect_vec3_near(v.spacing, glm::vec3(1.0f), 1e-5f);
    expect_vec3_near(v.origin, {64.8982f, 110.431f, -27.9255f}, 1e-3f);
    // The header's `space directions` (LPS), unit length: kept, not snapped to the axes.
    expect_vec3_near(v.direction[0], {-0.993592f, 0.0497049f, -0.101510f}, 1e-5f);
    expect_vec3_near(v.direction[1], {-0.0160050f, -0.950937f, -0.308971f}, 1e-5f);
    expect_vec3_near(v.direction[2], {-0.111887f, -0.305367f, 0.945639f}, 1e-5f);
    EXPECT_EQ(v.at(62, 80, 70), 170.0f);
    EXPECT_EQ(v.at(0, 0, 0), 0.0f);
    EXPECT_EQ(v.at(63, 106, 55), 255.0f);
    EXPECT_EQ(sum_of(v), 115231646.0);
    EXPECT_EQ(lv.info.range.min, 0.0f);
    EXPECT_EQ(lv.info.range.max, 255.0f);
}

TEST(LoadVolume, MetaImageHeadMr) {
    SNERT_REQUIRE_DATA();
    const LoadedVolume lv = open_volume(data_file("HeadMRVolume.mhd"));
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "MetaImage");
    EXPECT_EQ(lv.info.scalar_type, "uint8");
    EXPECT_EQ(v.dims, glm::ivec3(48, 62, 42));
    expect_vec3_near(v.spacing, glm::vec3(4.0f), 0.0f);
    expect_vec3_near(v.origin, glm::vec3(0.0f), 0.0f);
    EXPECT_EQ(v.direction, glm::mat3(1.0f));
    EXPECT_EQ(v.at(0, 0, 0), 1.0f);
    EXPECT_EQ(v.at(24, 31, 21), 79.0f);
    EXPECT_EQ(v.at(16, 41, 10), 86.0f);
    EXPECT_EQ(v.at(28, 39, 22), 255.0f);
    EXPECT_EQ(sum_of(v), 3058332.0);
    // Every sample equals the byte in the .raw file (uint8, no header).
    const Bytes raw = read_bytes(data_file("HeadMRVolume.raw"));
    ASSERT_EQ(raw.size(), v.samples.size());
    for (std::size_t i = 0; i < raw.size(); ++i) ASSERT_EQ(v.samples[i], float(raw[i])) << i;
}

TEST(LoadVolume, VtkCarotid) {
    SNERT_REQUIRE_DATA();
    const LoadedVolume lv = open_volume(data_file("carotid.vtk"));
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "VTK");
    EXPECT_EQ(lv.info.scalar_type, "float32");
    EXPECT_EQ(v.dims, glm::ivec3(76, 49, 45));
    expect_vec3_near(v.spacing, glm::vec3(1.0f), 0.0f);
    expect_vec3_near(v.origin, {100.0f, 80.0f, 1.0f}, 0.0f);
    EXPECT_EQ(v.at(0, 0, 0), 57.0f);
    EXPECT_EQ(v.at(38, 24, 22), 162.0f);
    EXPECT_EQ(v.at(25, 32, 11), 81.0f);
    EXPECT_EQ(v.at(75, 48, 44), 128.0f);
    EXPECT_EQ(v.at(50, 6, 22), 580.0f);
    EXPECT_EQ(sum_of(v), 16598647.0);
    EXPECT_EQ(lv.info.range.max, 580.0f);
    EXPECT_EQ(lv.info.nonfinite, 0u);
}

TEST(LoadVolume, OtsuSuggestionMatchesSources) {
    SNERT_REQUIRE_DATA();
    // SOURCES.md's Otsu thresholds, each within 1.5 bins of a 256-bin histogram.
    struct Case {
        std::string path;
        float otsu;
    };
    const Case cases[] = {{"HeadMRVolume.mhd", 41},
                          {"carotid.vtk", 80},
                          {"FLAIR.nrrd", 60},
                          {"totalseg_ct_abdomen/example_ct_sm.nii.gz", -492},
                          {"dicom_mr_head_t1_sag", 354}};
    for (const auto& c : cases) {
        const Volume v = load_volume(data_file(c.path));
        const Histogram h = make_histogram(v, 256);
        EXPECT_EQ(h.total(), v.voxel_count());
        EXPECT_NEAR(suggest_iso(v), c.otsu, 1.5 * h.bin_width()) << c.path;
    }
    RawOptions raw;
    raw.dims = {64, 64, 93};
    raw.type = ScalarType::UInt16;
    const Volume head = load_raw(data_file("headsq/quarter.1"), raw);
    EXPECT_NEAR(suggest_iso(head), 636.0, 1.5 * make_histogram(head).bin_width());
}

TEST(BadFiles, MissingEmptyAndUnknown) {
    TempFolder dir;
    expect_clear_error(error_of([&] { load_volume(dir.file("none.nrrd")); }), dir.file("none.nrrd"),
                       "no such file");
    write_bytes(dir.file("empty.nrrd"), {});
    expect_clear_error(error_of([&] { load_volume(dir.file("empty.nrrd")); }),
                       dir.file("empty.nrrd"), "empty file");
    write_bytes(dir.file("empty.nii.gz"), {});
    expect_clear_error(error_of([&] { load_volume(dir.file("empty.nii.gz")); }),
                       dir.file("empty.nii.gz"), "empty file");
    Bytes noise(1000);
    for (std::size_t i = 0; i < noise.size(); ++i) noise[i] = std::uint8_t(i * 7919 % 251);
    write_bytes(dir.file("noise.xyz"), noise);
    expect_clear_error(error_of([&] { load_volume(dir.file("noise.xyz")); }), dir.file("noise.xyz"),
                       "not a volume format");
    write_bytes(dir.file("noise.nrrd"), noise);
    expect_clear_error(error_of([&] { load_volume(dir.file("noise.nrrd")); }),
                       dir.file("noise.nrrd"), "not a volume format");
}

TEST(BadFiles, GzipThatIsNotGzip) {
    TempFolder dir;
    write_bytes(dir.file("fake.nii.gz"), text_bytes(std::string(600, 'x')));
    expect_clear_error(error_of([&] { load_volume(dir.file("fake.nii.gz")); }),
                       dir.file("fake.nii.gz"), "not gzip");
}

TEST(BadFiles, TruncatedMetaImageVtkNrrdAndRaw) {
    SNERT_REQUIRE_DATA();
    TempFolder dir;
    // MetaImage: header intact, .raw missing its last 1000 bytes.
    fs::copy_file(data_file("HeadMRVolume.mhd"), dir.file("head.mhd"));
    const Bytes raw = read_bytes(data_file("HeadMRVolume.raw"));
    write_bytes(dir.file("HeadMRVolume.raw"), Bytes(raw.begin(), raw.end() - 1000));
    expect_clear_error(error_of([&] { load_volume(dir.file("head.mhd")); }), dir.file("head.mhd"),
                       "truncated MetaImage");
    // VTK legacy binary, cut inside the samples.
    const Bytes vtk = read_bytes(data_file("carotid.vtk"));
    write_bytes(dir.file("carotid.vtk"), Bytes(vtk.begin(), vtk.begin() + 300000));
    expect_clear_error(error_of([&] { load_volume(dir.file("carotid.vtk")); }),
                       dir.file("carotid.vtk"), "truncated VTK");
    // NRRD with gzip encoding, cut: the stream inflates to fewer bytes than promised.
    const Bytes nrrd = read_bytes(data_file("FLAIR.nrrd"));
    write_bytes(dir.file("flair.nrrd"), Bytes(nrrd.begin(), nrrd.begin() + 500000));
    expect_clear_error(error_of([&] { load_volume(dir.file("flair.nrrd")); }),
                       dir.file("flair.nrrd"), "truncated NRRD: the header promises 2777600 bytes");
    // Raw: one slice file short of a byte.
    RawOptions options;
    options.dims = {64, 64, 93};
    options.type = ScalarType::UInt16;
    write_bytes(dir.file("head.raw"), Bytes(64 * 64 * 93 * 2 - 1));
    expect_clear_error(error_of([&] { load_raw(dir.file("head.raw"), options); }),
                       dir.file("head.raw"), "need 761856 bytes");
    // A slice series with a missing file.
    for (int k = 1; k <= 3; ++k) write_bytes(dir.file("sl." + std::to_string(k)), Bytes(8));
    options.dims = {2, 2, 4};
    expect_clear_error(error_of([&] { load_raw(dir.file("sl.1"), options); }), dir.file("sl.1"),
                       "sl.4 is missing");
}

TEST(BadFiles, HeaderThatLiesAboutSize) {
    TempFolder dir;
    // MetaImage claiming 100^3 shorts next to 1000 bytes.
    write_bytes(dir.file("lie.mhd"),
                text_bytes("ObjectType = Image\nNDims = 3\nDimSize = 100 100 100\n"
                           "ElementType = MET_SHORT\nElementDataFile = lie.raw\n"));
    write_bytes(dir.file("lie.raw"), Bytes(1000));
    expect_clear_error(error_of([&] { load_volume(dir.file("lie.mhd")); }), dir.file("lie.mhd"),
                       "promises 2000000 bytes");
    // .mha with LOCAL data.
    write_bytes(dir.file("lie.mha"),
                concat(text_bytes("NDims = 3\nDimSize = 64 64 64\nElementType = MET_UCHAR\n"
                                  "ElementDataFile = LOCAL\n"),
                       Bytes(4096)));
    expect_clear_error(error_of([&] { load_volume(dir.file("lie.mha")); }), dir.file("lie.mha"),
                       "truncated MetaImage");
    // NRRD claiming 64^3 shorts, raw encoding, 100 bytes present.
    write_bytes(dir.file("lie.nrrd"),
                concat(text_bytes(nrrd_header("short", "64 64 64", "raw")), Bytes(100)));
    expect_clear_error(error_of([&] { load_volume(dir.file("lie.nrrd")); }), dir.file("lie.nrrd"),
                       "promises 524288 bytes of samples, the file holds 100");
    // VTK whose POINT_DATA disagrees with DIMENSIONS.
    write_bytes(dir.file("lie.vtk"),
                concat(text_bytes("# vtk DataFile Version 3.0\nx\nBINARY\nDATASET "
                                  "STRUCTURED_POINTS\nDIMENSIONS 4 4 4\nSPACING 1 1 1\nORIGIN 0 "
                                  "0 0\nPOINT_DATA 8\nSCALARS s unsigned_char 1\nLOOKUP_TABLE "
                                  "default\n"),
                       Bytes(64)));
    expect_clear_error(error_of([&] { load_volume(dir.file("lie.vtk")); }), dir.file("lie.vtk"),
                       "POINT_DATA 8 does not match");
}

TEST(BadFiles, AbsurdDimensionsAreRefusedBeforeAllocating) {
    TempFolder dir;
    const std::string huge = "2147483648 2147483648 2147483648"; // 2^31 per axis
    write_bytes(dir.file("huge.nrrd"),
                concat(text_bytes(nrrd_header("unsigned char", huge, "raw")), Bytes(16)));
    expect_clear_error(error_of([&] { load_volume(dir.file("huge.nrrd")); }), dir.file("huge.nrrd"),
                       "absurd dimensions 2147483648 x 2147483648");
    write_bytes(dir.file("huge.mhd"),
                text_bytes("NDims = 3\nDimSize = " + huge +
                           "\nElementType = MET_UCHAR\nElementDataFile = huge.raw\n"));
    write_bytes(dir.file("huge.raw"), Bytes(16));
    expect_clear_error(error_of([&] { load_volume(dir.file("huge.mhd")); }), dir.file("huge.mhd"),
                       "absurd dimensions");
    // Large but representable: refused by the memory check, with the sizes.
    write_bytes(
        dir.file("big.nrrd"),
        concat(text_bytes(nrrd_header("unsigned char", "200000 200000 200000", "raw")), Bytes(16)));
    const std::string message = error_of([&] { load_volume(dir.file("big.nrrd")); });
    expect_clear_error(message, dir.file("big.nrrd"), "200000 x 200000 x 200000 samples need");
    EXPECT_NE(message.find("PiB as float32"), std::string::npos) << message;
    EXPECT_NE(message.find("of memory is available"), std::string::npos) << message;
    RawOptions raw;
    raw.dims = {0, 64, 64};
    EXPECT_THROW(load_raw(dir.file("huge.raw"), raw), std::invalid_argument);
}

TEST(BadFiles, MemoryLimitNamesBothSizes) {
    SNERT_REQUIRE_DATA();
    LoadOptions options;
    options.memory_limit_bytes = 10u << 20; // FLAIR needs 124*160*140*4 = 10.6 MiB
    const std::string message = error_of([&] { load_volume(data_file("FLAIR.nrrd"), options); });
    expect_clear_error(message, data_file("FLAIR.nrrd"), "124 x 160 x 140 samples need 10.6 MiB");
    EXPECT_NE(message.find("memory limit of 10.0 MiB"), std::string::npos) << message;
    options.memory_limit_bytes = 11u << 20;
    EXPECT_EQ(load_volume(data_file("FLAIR.nrrd"), options).dims, glm::ivec3(124, 160, 140));
}

TEST(BadFiles, UnknownSampleTypes) {
    TempFolder dir;
    write_bytes(dir.file("block.nrrd"),
                concat(text_bytes("NRRD0004\ntype: block\nblock size: 3\ndimension: 3\nsizes: 2 2 "
                                  "2\nencoding: raw\n\n"),
                       Bytes(24)));
    expect_clear_error(error_of([&] { load_volume(dir.file("block.nrrd")); }),
                       dir.file("block.nrrd"), "unsupported NRRD type 'block'");
    write_bytes(dir.file("string.mhd"),
                text_bytes("NDims = 3\nDimSize = 2 2 2\nElementType = MET_STRING\n"
                           "ElementDataFile = string.raw\n"));
    write_bytes(dir.file("string.raw"), Bytes(8));
    expect_clear_error(error_of([&] { load_volume(dir.file("string.mhd")); }),
                       dir.file("string.mhd"), "unsupported MetaImage ElementType MET_STRING");
    // NIfTI-1 with datatype 128 (RGB24).
    Bytes header(352);
    const auto put16 = [&](std::size_t at, std::int16_t v) { std::memcpy(&header[at], &v, 2); };
    const std::int32_t sizeof_hdr = 348;
    std::memcpy(&header[0], &sizeof_hdr, 4);
    put16(40, 3);
    put16(42, 2);
    put16(44, 2);
    put16(46, 2);
    put16(70, 128);
    put16(72, 24);
    const float vox_offset = 352.0f, one = 1.0f;
    std::memcpy(&header[108], &vox_offset, 4);
    for (int i = 0; i < 4; ++i) std::memcpy(&header[76 + 4 * i], &one, 4);
    std::memcpy(&header[344], "n+1\0", 4);
    write_bytes(dir.file("rgb.nii"), concat(header, Bytes(24)));
    expect_clear_error(error_of([&] { load_volume(dir.file("rgb.nii")); }), dir.file("rgb.nii"),
                       "unsupported NIfTI datatype 128 (RGB24)");
    EXPECT_THROW(parse_scalar_type("int128"), std::invalid_argument);
}
