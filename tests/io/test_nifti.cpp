// NIfTI through snert's own sample reader and ITK's geometry: the CT and its label map from the
// shared test data, world positions against the file's own sform, and truncated files.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "core/marching_cubes.h"
#include "core/mesh.h"
#include "core/segmentation.h"
#include "core/volume_stats.h"
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

TEST(LoadVolume, NiftiCtAbdomenInLps) {
    SNERT_REQUIRE_DATA();
    const LoadedVolume lv = open_volume(data_file("totalseg_ct_abdomen/example_ct_sm.nii.gz"));
    const Volume& v = lv.volume;
    EXPECT_EQ(lv.info.format, "NIfTI");
    EXPECT_EQ(lv.info.scalar_type, "int16");
    EXPECT_EQ(v.dims, glm::ivec3(122, 101, 30));
    expect_vec3_near(v.spacing, glm::vec3(3.0f), 0.0f);
    // sform (RAS) translation (-177.956, 11.319, 94.302) becomes LPS (177.956, -11.319, 94.302).
    expect_vec3_near(v.origin, {177.956f, -11.319f, 94.3018f}, 1e-3f);
    expect_vec3_near(v.direction[0], {-1, 0, 0}, 1e-6f);
    expect_vec3_near(v.direction[1], {0, -1, 0}, 1e-6f);
    expect_vec3_near(v.direction[2], {0, 0, 1}, 1e-6f);
    EXPECT_EQ(v.at(0, 0, 0), -1024.0f);
    EXPECT_EQ(v.at(61, 50, 15), 0.0f);
    EXPECT_EQ(v.at(40, 67, 7), -104.0f);
    EXPECT_EQ(v.at(121, 100, 29), -997.0f);
    EXPECT_EQ(v.at(63, 35, 2), 1207.0f);
    EXPECT_EQ(sum_of(v), -130894872.0);
    EXPECT_EQ(lv.info.range.min, -1100.0f);
    EXPECT_EQ(lv.info.range.max, 1207.0f);
}

TEST(LoadVolume, NiftiLabelMapWithHeaderExtension) {
    SNERT_REQUIRE_DATA();
    // vox_offset 13168: the data starts after a 12.8 kB header extension.
    const Volume labels = load_volume(data_file("totalseg_ct_abdomen/example_seg.nii.gz"));
    EXPECT_EQ(labels.dims, glm::ivec3(122, 101, 30));
    EXPECT_EQ(segment_label(labels, 5).count_inside(), 38634u); // liver
    EXPECT_EQ(sum_of(labels), 2734697.0);
    const std::vector<int> present = labels_present(labels);
    EXPECT_EQ(present.size(), 42u); // 41 labels and the background
    EXPECT_EQ(present.front(), 0);
    EXPECT_EQ(present.back(), 117);
}

// The same CT as NIfTI (RAS sform) and as NRRD written here from the NIfTI's bytes, once in
// LPS and once in RAS space: Marching Cubes meshes in world millimetres must coincide, and
// sit where the NIfTI's own sform (parsed here, not by ITK) puts them.
TEST(LoadVolume, NiftiAndNrrdMeshesCoincideInWorld) {
    SNERT_REQUIRE_DATA();
    const std::string nifti = data_file("totalseg_ct_abdomen/example_ct_sm.nii.gz");
    const Bytes nii = gunzip(read_bytes(nifti));
    ASSERT_GE(nii.size(), 352u);
    glm::mat4 sform(1.0f); // column-major: sform[c][r]
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) sform[c][r] = load_le<float>(nii, 280 + 16 * r + 4 * c);
    const std::size_t offset = std::size_t(load_le<float>(nii, 108));
    const Bytes samples(nii.begin() + std::ptrdiff_t(offset), nii.end());

    auto vector_text = [](glm::vec3 v) {
        std::ostringstream out;
        out.precision(9);
        out << "(" << v.x << "," << v.y << "," << v.z << ")";
        return out.str();
    };
    auto write_nrrd = [&](const std::string& path, const std::string& space, glm::vec3 flip) {
        std::string extra = "space: " + space + "\nspace directions:";
        // Appended piece by piece: "text" + std::string&& trips GCC 12's -Wrestrict (PR 105329).
        for (int c = 0; c < 3; ++c)
            extra.append(" ").append(vector_text(flip * glm::vec3(sform[c])));
        extra.append("\nspace origin: ")
            .append(vector_text(flip * glm::vec3(sform[3])))
            .append("\n");
        write_bytes(path,
                    concat(text_bytes(nrrd_header("short", "122 101 30", "raw", extra)), samples));
    };
    TempFolder dir;
    write_nrrd(dir.file("ct_lps.nrrd"), "left-posterior-superior", {-1, -1, 1});
    write_nrrd(dir.file("ct_ras.nrrd"), "right-anterior-superior", {1, 1, 1});

    const Volume from_nifti = load_volume(nifti);
    const MarchingCubesOptions mc{200.0f, InsideIs::Above};
    const Mesh index_mesh = marching_cubes(from_nifti, mc);
    ASSERT_GT(index_mesh.vertex_count(), 1000u);
    const Mesh world = mesh_to_world(index_mesh, from_nifti);
    for (const std::string name : {"ct_lps.nrrd", "ct_ras.nrrd"}) {
        const Volume from_nrrd = load_volume(dir.file(name));
        ASSERT_EQ(from_nrrd.samples, from_nifti.samples) << name;
        const Mesh other = mesh_to_world(marching_cubes(from_nrrd, mc), from_nrrd);
        ASSERT_EQ(other.vertex_count(), world.vertex_count()) << name;
        ASSERT_EQ(other.indices, world.indices) << name;
        float worst = 0.0f;
        for (std::size_t i = 0; i < world.vertex_count(); ++i)
            worst = std::max(worst, glm::length(other.positions[i] - world.positions[i]));
        EXPECT_LT(worst, 1e-3f) << name << ": largest distance between the meshes, mm";
    }
    // Where the scanner put them: LPS = diag(-1, -1, 1) * (sform * index).
    float worst = 0.0f;
    for (std::size_t i = 0; i < world.vertex_count(); ++i) {
        const glm::vec3 ras = glm::vec3(sform * glm::vec4(index_mesh.positions[i], 1.0f));
        worst = std::max(worst, glm::length(world.positions[i] - ras * glm::vec3(-1, -1, 1)));
    }
    EXPECT_LT(worst, 1e-3f) << "largest distance from the sform's positions, mm";
}

TEST(BadFiles, TruncatedNiftiGzAndNii) {
    SNERT_REQUIRE_DATA();
    TempFolder dir;
    const Bytes gz = read_bytes(data_file("totalseg_ct_abdomen/example_ct_sm.nii.gz"));
    // Cut the compressed stream in half: ITK would zero-fill the missing samples.
    write_bytes(dir.file("half.nii.gz"),
                Bytes(gz.begin(), gz.begin() + std::ptrdiff_t(gz.size() / 2)));
    expect_clear_error(error_of([&] { load_volume(dir.file("half.nii.gz")); }),
                       dir.file("half.nii.gz"), "truncated");
    // Only the header and 1000 bytes of samples, uncompressed.
    const Bytes nii = gunzip(gz);
    write_bytes(dir.file("short.nii"), Bytes(nii.begin(), nii.begin() + 1352));
    const std::string message = error_of([&] { load_volume(dir.file("short.nii")); });
    expect_clear_error(message, dir.file("short.nii"), "truncated NIfTI");
    EXPECT_NE(message.find("739320"), std::string::npos) << message; // 122*101*30*2 bytes
    // The whole header but no sample at all, gzip again.
    write_bytes(dir.file("header.nii.gz"), gzip(Bytes(nii.begin(), nii.begin() + 352)));
    expect_clear_error(error_of([&] { load_volume(dir.file("header.nii.gz")); }),
                       dir.file("header.nii.gz"), "truncated");
}
