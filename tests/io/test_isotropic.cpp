// Resampling to cubic voxels (io/isotropic.h): the grid (dims, spacing, origin, the world extent
// kept), the grey values (a linear ramp comes back exactly), a label's mask cut at 0.5, the same
// bits for any thread count, the refusals, and the path through open_source.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "core/parallel.h"
#include "io/isotropic.h"
#include "io/source.h"
#include "support/expect_error.h"
#include "support/temp_folder.h"
#include "volume_files.h"

namespace snert {
namespace {

using test::error_of;
using test::expect_contains;

// A ramp, linear in world millimetres, on an anisotropic grid with a rotated frame.
float ramp(glm::vec3 world) {
    return 2.0f * world.x - 0.5f * world.y + 3.0f * world.z + 7.0f;
}

Volume ramp_volume() {
    Volume v = make_volume({6, 5, 4});
    v.spacing = {1.0f, 1.5f, 3.0f};
    v.origin = {10.0f, -5.0f, 2.5f};
    // x index axis along world y, y along -x, z along z: a direction that is not the identity.
    v.direction = glm::mat3(glm::vec3(0, 1, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 0, 1));
    for (int z = 0; z < v.dims.z; ++z)
        for (int y = 0; y < v.dims.y; ++y)
            for (int x = 0; x < v.dims.x; ++x)
                v.samples[v.index(x, y, z)] = ramp(index_to_world(v, glm::vec3(x, y, z)));
    return v;
}

TEST(Isotropic, GridKeepsOriginDirectionAndExtent) {
    const Volume v = ramp_volume();
    // Default edge: the smallest spacing (1 mm). Extents 5, 6 and 9 mm are multiples of it.
    const IsotropicGrid g = isotropic_grid("ramp", v, 0.0f);
    EXPECT_EQ(g.edge, 1.0f);
    EXPECT_EQ(g.dims, glm::ivec3(6, 7, 10));
    EXPECT_EQ(g.origin, v.origin);
    EXPECT_EQ(g.direction, v.direction);
    // A chosen edge: 0.7 mm fits 7, 8 and 12 times into 5, 6 and 9 mm; the far end is kept to
    // within one new voxel.
    const IsotropicGrid h = isotropic_grid("ramp", v, 0.7f);
    EXPECT_EQ(h.dims, glm::ivec3(8, 9, 13));
    for (int a = 0; a < 3; ++a) {
        const double stored = (v.dims[a] - 1) * double(v.spacing[a]);
        const double kept = (h.dims[a] - 1) * double(h.edge);
        EXPECT_LE(kept, stored + 1e-5) << "axis " << a;
        EXPECT_GT(kept, stored - h.edge) << "axis " << a;
    }
    // A grid that is cubic already, at its own edge, is left alone.
    Volume cubic = make_volume({4, 4, 4});
    cubic.spacing = glm::vec3(0.8f);
    EXPECT_TRUE(on_grid(cubic, isotropic_grid("cubic", cubic, 0.0f)));
    EXPECT_FALSE(on_grid(cubic, isotropic_grid("cubic", cubic, 0.4f)));
    EXPECT_FALSE(on_grid(v, g));
}

TEST(Isotropic, LinearRampIsReproduced) {
    const Volume v = ramp_volume();
    const IsotropicGrid g = isotropic_grid("ramp", v, 0.7f);
    const Volume r = resample_linear(v, g);
    ASSERT_EQ(r.dims, g.dims);
    EXPECT_EQ(r.spacing, glm::vec3(0.7f));
    EXPECT_EQ(r.origin, v.origin);
    EXPECT_EQ(r.direction, v.direction);
    // Linear interpolation is exact on a linear function: every new sample holds the ramp at
    // its own world position (values up to about 60: float rounding only).
    for (int z = 0; z < r.dims.z; ++z)
        for (int y = 0; y < r.dims.y; ++y)
            for (int x = 0; x < r.dims.x; ++x)
                ASSERT_NEAR(r.at(x, y, z), ramp(index_to_world(r, glm::vec3(x, y, z))), 2e-4f)
                    << x << " " << y << " " << z;
}

TEST(Isotropic, MaskIsResampledLinearlyAndCutAtHalf) {
    // Inside where x >= 1 and z >= 2 on a 1 x 1 x 3 mm grid.
    Volume geometry = make_volume({4, 3, 5});
    geometry.spacing = {1.0f, 1.0f, 3.0f};
    Segmentation mask;
    mask.dims = geometry.dims;
    mask.inside.assign(geometry.voxel_count(), 0);
    for (int z = 2; z < 5; ++z)
        for (int y = 0; y < 3; ++y)
            for (int x = 1; x < 4; ++x) mask.inside[mask.index(x, y, z)] = 1;
    const IsotropicGrid g = isotropic_grid("mask", geometry, 0.0f);
    ASSERT_EQ(g.dims, glm::ivec3(4, 3, 13));
    const Segmentation r = resample_mask(mask, geometry, g);
    ASSERT_EQ(r.dims, g.dims);
    // New slice k lies at stored z = k / 3: the 0/1 step between z = 1 and 2 interpolates to
    // 1/3 at k = 4 (outside) and 2/3 at k = 5 (inside).
    for (int z = 0; z < r.dims.z; ++z)
        for (int y = 0; y < r.dims.y; ++y)
            for (int x = 0; x < r.dims.x; ++x)
                EXPECT_EQ(r.at(x, y, z), x >= 1 && z >= 5) << x << " " << y << " " << z;
}

TEST(Isotropic, MaskMatchesTrilinearCutOfASphere) {
    Volume geometry = make_volume({12, 11, 6});
    geometry.spacing = {0.9f, 1.1f, 2.6f};
    Segmentation mask;
    mask.dims = geometry.dims;
    mask.inside.assign(geometry.voxel_count(), 0);
    for (int z = 0; z < 6; ++z)
        for (int y = 0; y < 11; ++y)
            for (int x = 0; x < 12; ++x) {
                const glm::vec3 w = index_to_world(geometry, glm::vec3(x, y, z));
                mask.inside[mask.index(x, y, z)] =
                    glm::length(w - glm::vec3(5.0f, 5.5f, 6.5f)) < 4.5f ? 1 : 0;
            }
    const IsotropicGrid g = isotropic_grid("sphere", geometry, 0.5f);
    const Segmentation r = resample_mask(mask, geometry, g);
    Volume resampled_geometry = make_volume(g.dims);
    resampled_geometry.spacing = glm::vec3(g.edge);
    // core's own trilinear interpolation of the 0/1 volume, cut at 0.5, away from exact ties.
    const Volume ones = mask_volume(mask, geometry);
    std::size_t compared = 0, inside = 0;
    for (int z = 0; z < g.dims.z; ++z)
        for (int y = 0; y < g.dims.y; ++y)
            for (int x = 0; x < g.dims.x; ++x) {
                const glm::vec3 w = index_to_world(resampled_geometry, glm::vec3(x, y, z));
                const float v = sample_trilinear(ones, world_to_index(geometry, w));
                if (std::abs(v - 0.5f) < 1e-4f) continue;
                ++compared;
                inside += r.at(x, y, z);
                ASSERT_EQ(r.at(x, y, z), v >= 0.5f) << x << " " << y << " " << z;
            }
    EXPECT_GT(compared, r.inside.size() * 9 / 10);
    EXPECT_GT(inside, 100u);
}

TEST(Isotropic, SameBitsForAnyThreadCount) {
    Volume v = make_volume({37, 29, 13});
    v.spacing = {0.7f, 1.3f, 2.9f};
    for (std::size_t i = 0; i < v.samples.size(); ++i)
        v.samples[i] = std::sin(0.37f * float(i)) * 100.0f + float(i % 17);
    const IsotropicGrid g = isotropic_grid("noise", v, 0.45f);
    Volume one, many;
    {
        ThreadLimit limit(1);
        one = resample_linear(v, g);
    }
    {
        ThreadLimit limit(8);
        many = resample_linear(v, g);
    }
    ASSERT_EQ(one.samples.size(), many.samples.size());
    EXPECT_EQ(
        std::memcmp(one.samples.data(), many.samples.data(), one.samples.size() * sizeof(float)),
        0);
}

TEST(Isotropic, RefusesWhatDoesNotFitWithTheSizes) {
    Volume v = make_volume({256, 256, 35});
    v.spacing = {1.0f, 1.0f, 4.8f};
    const IsotropicGrid g = isotropic_grid("head.nrrd", v, 0.0f);
    EXPECT_EQ(g.dims, glm::ivec3(256, 256, 164));
    // Two float32 grids of 256 x 256 x 164 (the new one and ITK's output): 82 MiB.
    EXPECT_EQ(isotropic_bytes_needed(v, g, false), 2ull * 256 * 256 * 164 * 4);
    EXPECT_GT(isotropic_bytes_needed(v, g, true), isotropic_bytes_needed(v, g, false));
    const std::string message = error_of<std::runtime_error>(
        [&] { check_isotropic_memory("head.nrrd", v, g, false, 64ull << 20); });
    io_test::expect_clear_error(message, "head.nrrd", "cubic voxels of 1 mm");
    expect_contains(message, {"256 x 256 x 35 samples", "spacing 1 x 1 x 4.8 mm", "256 x 256 x 164",
                              "82.0 MiB", "memory limit of 64.0 MiB"});
    EXPECT_NO_THROW(check_isotropic_memory("head.nrrd", v, g, false, 100ull << 20));
    // Absurd edges: an axis of more samples than snert addresses, or a product that overflows.
    io_test::expect_clear_error(
        error_of<std::runtime_error>([&] { isotropic_grid("head.nrrd", v, 1e-9f); }), "head.nrrd",
        "samples along an axis");
    io_test::expect_clear_error(
        error_of<std::runtime_error>([&] { isotropic_grid("head.nrrd", v, 1e-4f); }), "head.nrrd",
        "more samples than snert can address");
    io_test::expect_clear_error(
        error_of<std::runtime_error>([&] { isotropic_grid("head.nrrd", v, -1.0f); }), "head.nrrd",
        "positive number");
    io_test::expect_clear_error(
        error_of<std::runtime_error>([&] { isotropic_grid("head.nrrd", v, NAN); }), "head.nrrd",
        "positive number");
}

// A float NRRD on a 1 x 1 x 3 mm grid: grey values z * 10 + x, or label 4 where z >= 2.
std::string write_nrrd(const test::TempFolder& folder, const std::string& name, bool labels) {
    std::vector<float> values(5 * 4 * 6);
    for (int z = 0; z < 6; ++z)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 5; ++x)
                values[std::size_t((z * 4 + y) * 5 + x)] =
                    labels ? (z >= 2 ? 4.0f : 0.0f) : float(z * 10 + x);
    const std::string path = folder.file(name);
    test::write_bytes(path, io_test::concat(io_test::text_bytes(io_test::nrrd_header(
                                                "float", "5 4 6", "raw", "spacings: 1 1 3\n")),
                                            io_test::as_bytes(values)));
    return path;
}

TEST(Isotropic, OpenSourceResamplesGreyAndLabel) {
    test::TempFolder folder;
    SourceSpec spec;
    spec.input = write_nrrd(folder, "grey.nrrd", false);
    spec.labels = write_nrrd(folder, "labels.nrrd", true);
    spec.label = 4;
    const Source stored = open_source(spec);
    spec.isotropic = 0.0f;
    const Source s = open_source(spec);
    ASSERT_TRUE(s.volume && s.mask);
    EXPECT_EQ(s.volume->dims, glm::ivec3(5, 4, 16));
    EXPECT_EQ(s.volume->spacing, glm::vec3(1.0f));
    EXPECT_EQ(s.mask->dims, s.volume->dims);
    expect_contains(s.description, {"resampled to 5x4x16, cubic voxels of 1 mm"});
    // The grey ramp along z, 10 per 3 mm, comes back at every new slice.
    EXPECT_NEAR(s.volume->at(2, 1, 7), 2.0f + 70.0f / 3.0f, 1e-4f);
    // The label's boundary between stored slices 1 and 2 (z = 3 and 6 mm) is cut at 4.5 mm.
    EXPECT_FALSE(s.mask->at(0, 0, 4));
    EXPECT_TRUE(s.mask->at(0, 0, 5));
    // The labels listed and their voxels are the stored map's.
    ASSERT_EQ(s.labels_present.size(), stored.labels_present.size());
    EXPECT_EQ(s.labels_present.back().voxels, stored.labels_present.back().voxels);

    // Too little memory: refused before the grid is allocated, naming the file and the sizes.
    spec.memory_limit = 1000;
    const std::string message = error_of<std::runtime_error>([&] { open_source(spec); });
    io_test::expect_clear_error(message, spec.input, "5 x 4 x 16");
    expect_contains(message, {"5 x 4 x 6 samples", "spacing 1 x 1 x 3 mm"});
}

TEST(Isotropic, CubicFileIsKeptAndPhantomsRefuse) {
    test::TempFolder folder;
    std::vector<float> values(27, 1.0f);
    SourceSpec spec;
    spec.input = folder.file("cubic.nrrd");
    test::write_bytes(spec.input,
                      io_test::concat(io_test::text_bytes(io_test::nrrd_header(
                                          "float", "3 3 3", "raw", "spacings: 2 2 2\n")),
                                      io_test::as_bytes(values)));
    spec.isotropic = 0.0f;
    const Source s = open_source(spec);
    EXPECT_EQ(s.volume->dims, glm::ivec3(3));
    expect_contains(s.description, {"cubic already"});

    SourceSpec phantom;
    phantom.input = "phantom:sphere";
    phantom.isotropic = 0.0f;
    test::expect_error<std::invalid_argument>([&] { open_source(phantom); },
                                              {"phantom:sphere", "cubic already"});
}

} // namespace
} // namespace snert
