// DICOM through GDCM in a child process: the MR series from the shared test data in slice
// order, chosen by file or by uid; damaged copies (a cut header that makes GDCM abort, cut pixel
// data, a missing slice) that fail with a clear error while this process lives on; and the
// Pixel Data check that finds cut slices before GDCM zero-fills them.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>

#include "io/dicom_pixel_data.h"
#include "io/dicom_series.h"
#include "io/load_volume.h"
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

TEST(LoadVolume, DicomFolderReadsTheSeriesInSliceOrder) {
    SNERT_REQUIRE_DATA();
    const LoadedVolume lv = open_volume(data_file("dicom_mr_head_t1_sag"));
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "DICOM");
    EXPECT_EQ(lv.info.scalar_type, "uint16");
    EXPECT_EQ(lv.info.files, 35u);
    EXPECT_FALSE(lv.info.series_uid.empty());
    EXPECT_EQ(v.dims, glm::ivec3(256, 256, 35));
    expect_vec3_near(v.spacing, {1.015625f, 1.015625f, 4.8f}, 1e-4f); // z from the positions
    expect_vec3_near(v.origin, {81.6f, -130.0f, 130.0f}, 1e-3f);
    expect_vec3_near(v.direction[0], {0, 1, 0}, 1e-6f);
    expect_vec3_near(v.direction[1], {0, 0, -1}, 1e-6f);
    expect_vec3_near(v.direction[2], {-1, 0, 0}, 1e-6f);
    EXPECT_EQ(v.at(128, 128, 17), 484.0f);
    EXPECT_EQ(v.at(85, 170, 8), 421.0f);
    EXPECT_EQ(v.at(187, 246, 22), 1948.0f);
    EXPECT_EQ(sum_of(v), 516841282.0);
    // Slice 0 is the file named 0035_* (x = +81.6): its pixel data ends the file, uint16 LE.
    std::string last_file;
    for (const auto& entry : fs::directory_iterator(data_file("dicom_mr_head_t1_sag")))
        if (entry.path().filename().string().rfind("0035_", 0) == 0)
            last_file = entry.path().string();
    const Bytes dcm = read_bytes(last_file);
    const std::size_t pixels = std::size_t(256) * 256;
    ASSERT_GE(dcm.size(), pixels * 2);
    for (std::size_t i = 0; i < pixels; i += 97)
        ASSERT_EQ(v.samples[i], float(load_le<std::uint16_t>(dcm, dcm.size() - pixels * 2 + 2 * i)))
            << i;
}

TEST(LoadVolume, DicomSeriesByFileAndByUid) {
    SNERT_REQUIRE_DATA();
    const auto series = list_dicom_series(data_file("dicom_mr_head_t1_sag"));
    ASSERT_EQ(series.size(), 1u);
    EXPECT_EQ(series[0].files, 35u);
    LoadOptions options;
    options.dicom_series_uid = series[0].uid;
    const LoadedVolume by_uid = open_volume(data_file("dicom_mr_head_t1_sag"), options);
    EXPECT_EQ(by_uid.info.series_uid, series[0].uid);
    EXPECT_EQ(by_uid.volume.dims, glm::ivec3(256, 256, 35));
    // One file of the series names the whole series.
    std::string one_file;
    for (const auto& entry : fs::directory_iterator(data_file("dicom_mr_head_t1_sag")))
        if (entry.path().filename().string().rfind("0010_", 0) == 0)
            one_file = entry.path().string();
    const Volume by_file = load_volume(one_file);
    EXPECT_EQ(by_file.samples, by_uid.volume.samples);

    options.dicom_series_uid = "1.2.3.4";
    const std::string message = error_of<std::invalid_argument>(
        [&] { open_volume(data_file("dicom_mr_head_t1_sag"), options); });
    expect_clear_error(message, data_file("dicom_mr_head_t1_sag"), "no DICOM series 1.2.3.4");
    EXPECT_NE(message.find(series[0].uid), std::string::npos) << message;
}

// A copy of the DICOM series with one file damaged.
struct DamagedDicom {
    TempFolder dir;
    std::string damaged;
    explicit DamagedDicom(std::uintmax_t keep_bytes) {
        for (const auto& entry : fs::directory_iterator(data_file("dicom_mr_head_t1_sag"))) {
            const fs::path to = dir.path() / entry.path().filename();
            fs::copy_file(entry.path(), to);
            fs::permissions(to, fs::perms::owner_read | fs::perms::owner_write);
            if (entry.path().filename().string().rfind("0010_", 0) == 0) damaged = to.string();
        }
        fs::resize_file(damaged, keep_bytes);
    }
};

TEST(BadFiles, TruncatedDicomHeaderDoesNotAbortTheProcess) {
    SNERT_REQUIRE_DATA();
    // Cut inside the header: GDCM's assert fires (SIGABRT) in the reader's child process.
    DamagedDicom dicom(2000);
    const std::string folder = dicom.dir.path().string();
    const std::string message = error_of([&] { load_volume(folder); });
    expect_clear_error(message, folder, "the DICOM reader crashed");
    // This process is alive, and the intact series still loads.
    EXPECT_EQ(load_volume(data_file("dicom_mr_head_t1_sag")).dims, glm::ivec3(256, 256, 35));
}

TEST(BadFiles, TruncatedDicomPixelDataAndMissingSlice) {
    SNERT_REQUIRE_DATA();
    {
        DamagedDicom dicom(265114 - 1000); // the pixel data is short of 1000 bytes
        const std::string message = error_of([&] { load_volume(dicom.dir.path().string()); });
        expect_clear_error(message, dicom.damaged, "truncated DICOM");
    }
    {
        DamagedDicom dicom(1000); // GDCM skips this file: the series has a gap
        const std::string message = error_of([&] { load_volume(dicom.dir.path().string()); });
        EXPECT_NE(message.find("missing, damaged or unevenly spaced slices"), std::string::npos)
            << message;
    }
}

TEST(BadFiles, FolderWithoutDicom) {
    TempFolder dir;
    write_bytes(dir.file("notes.txt"), text_bytes("no images here\n"));
    expect_clear_error(error_of([&] { load_volume(dir.path().string()); }), dir.path().string(),
                       "no DICOM series found");
    EXPECT_TRUE(list_dicom_series(dir.path().string()).empty());
}

TEST(HeaderChecks, DicomPixelDataCheck) {
    // Explicit VR little endian: tag, "OW", 2 reserved bytes, 32-bit length, then the value.
    Bytes file(200, 0);
    const std::uint8_t element[] = {0xE0, 0x7F, 0x10, 0x00, 'O', 'W', 0, 0, 8, 0, 0, 0};
    std::memcpy(&file[100], element, sizeof element);
    auto check = detail::check_dicom_pixel_data(file.data(), 120, 8, false);
    EXPECT_EQ(check.state, detail::PixelDataCheck::Complete);
    EXPECT_EQ(check.value_offset, 112u);
    check = detail::check_dicom_pixel_data(file.data(), 115, 8, false);
    EXPECT_EQ(check.state, detail::PixelDataCheck::Truncated);
    EXPECT_EQ(check.available, 3u);
    check = detail::check_dicom_pixel_data(file.data(), 120, 16, false);
    EXPECT_EQ(check.state, detail::PixelDataCheck::NotFound);
}
