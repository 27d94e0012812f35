#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/parallel.h"
#include "core/phantom.h"
#include "core/segmentation.h"
#include "core/volume.h"
#include "core/volume_stats.h"

using namespace snert;

namespace {

// I = 2x - 3y + 0.5z + 7: trilinear sampling and every gradient must be exact on it.
Volume linear_ramp(glm::ivec3 dims) {
    Volume v = make_volume(dims);
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x)
                v.samples[v.index(x, y, z)] = 2.0f * x - 3.0f * y + 0.5f * z + 7.0f;
    return v;
}

// Samples without structure, so that every corner and neighbour of a cell differs.
Volume wavy_volume(glm::ivec3 dims) {
    Volume v = make_volume(dims);
    for (std::size_t i = 0; i < v.samples.size(); ++i)
        v.samples[i] = std::sin(0.7f * float(i)) * 100.0f + float(i % 7);
    return v;
}

// A seeded linear congruential sequence in [0, 1): the same points on every platform.
struct UnitRandom {
    std::uint32_t state;
    float operator()() {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    }
};

} // namespace

TEST(Volume, TrilinearIsExactOnLinearField) {
    const Volume v = linear_ramp({6, 5, 4});
    for (glm::vec3 p :
         {glm::vec3(0.25f, 1.5f, 2.75f), glm::vec3(4.9f, 3.1f, 0.0f), glm::vec3(5.0f, 4.0f, 3.0f)})
        EXPECT_NEAR(sample_trilinear(v, p), 2 * p.x - 3 * p.y + 0.5f * p.z + 7, 1e-4f);
}

TEST(Volume, TrilinearClampsOutsideTheGrid) {
    const Volume v = linear_ramp({4, 4, 4});
    EXPECT_FLOAT_EQ(sample_trilinear(v, {-3.0f, 0.0f, 0.0f}), v.at(0, 0, 0));
    EXPECT_FLOAT_EQ(sample_trilinear(v, {10.0f, 3.0f, 3.0f}), v.at(3, 3, 3));
}

TEST(Volume, CentralGradientOfLinearField) {
    const Volume v = linear_ramp({6, 6, 6});
    const glm::vec3 g = gradient_central(v, {2.3f, 3.7f, 1.2f});
    EXPECT_NEAR(g.x, 2.0f, 1e-5f);
    EXPECT_NEAR(g.y, -3.0f, 1e-5f);
    EXPECT_NEAR(g.z, 0.5f, 1e-5f);
    // One-sided at the border, still exact for a linear field.
    const glm::vec3 edge = gradient_central(v, {0.0f, 0.0f, 5.0f});
    EXPECT_NEAR(edge.x, 2.0f, 1e-5f);
    EXPECT_NEAR(edge.z, 0.5f, 1e-5f);
}

// The fused sampler must equal the two separate ones bit for bit, at the border, outside the
// grid and on one-sample axes too, or a relaxation would change with it.
TEST(Volume, ValueAndGradientTogetherEqualTheSeparateSamplers) {
    for (glm::ivec3 dims : {glm::ivec3(7, 6, 5), glm::ivec3(1, 4, 3), glm::ivec3(2, 1, 2)}) {
        const Volume v = wavy_volume(dims);
        UnitRandom next{12345u};
        for (int k = 0; k < 500; ++k) {
            const glm::vec3 p = glm::vec3(next(), next(), next()) * (glm::vec3(dims) + 1.0f) - 0.5f;
            const ValueGradient vg = sample_value_gradient(v, p);
            EXPECT_EQ(vg.value, sample_trilinear(v, p));
            const glm::vec3 g = gradient_central(v, p);
            EXPECT_EQ(vg.gradient.x, g.x);
            EXPECT_EQ(vg.gradient.y, g.y);
            EXPECT_EQ(vg.gradient.z, g.z);
        }
    }
}

// The kept corners of a cell are the ones sample_value_gradient would compute: points visited
// in runs within one cell (as a triangle's sample points are) and jumps to other cells, the
// border's one-sided differences and cells clamped to the grid included, give the same bits.
TEST(Volume, KeptCellCornersGiveTheSameValueAndGradient) {
    for (glm::ivec3 dims : {glm::ivec3(7, 6, 5), glm::ivec3(1, 4, 3), glm::ivec3(2, 1, 2)}) {
        const Volume v = wavy_volume(dims);
        UnitRandom next{777u};
        CellCorners kept;
        int reused = 0;
        for (int k = 0; k < 300; ++k) {
            const glm::vec3 cell =
                glm::floor(glm::vec3(next(), next(), next()) * (glm::vec3(dims) + 1.0f)) - 1.0f;
            for (int j = 0; j < 4; ++j) {
                const glm::vec3 p = cell + glm::vec3(next(), next(), next());
                const glm::ivec3 before = kept.base;
                const ValueGradient cached = sample_value_gradient(v, p, kept);
                reused += kept.base == before ? 1 : 0;
                const ValueGradient fresh = sample_value_gradient(v, p);
                ASSERT_EQ(cached.value, fresh.value);
                ASSERT_EQ(cached.gradient.x, fresh.gradient.x);
                ASSERT_EQ(cached.gradient.y, fresh.gradient.y);
                ASSERT_EQ(cached.gradient.z, fresh.gradient.z);
            }
        }
        EXPECT_GT(reused, 600); // most points of a run find their cell kept
    }
}

// The cache of eight cells gives the same bits as sampling afresh, for points that wander back
// and forth among neighbouring cells (a small triangle's sample points), clamped cells at the
// border included; neighbouring cells never evict each other.
TEST(Volume, CellCornerCacheGivesTheSameValueAndGradient) {
    for (glm::ivec3 dims : {glm::ivec3(7, 6, 5), glm::ivec3(1, 4, 3), glm::ivec3(2, 1, 2)}) {
        const Volume v = wavy_volume(dims);
        UnitRandom next{4242u};
        CellCornerCache kept;
        int samples = 0, fills = 0;
        for (int k = 0; k < 200; ++k) {
            // A 2 x 2 x 2 block of cells (some outside the grid, clamped), visited at random.
            const glm::vec3 corner =
                glm::floor(glm::vec3(next(), next(), next()) * (glm::vec3(dims) + 1.0f)) - 1.0f;
            for (int j = 0; j < 12; ++j) {
                const glm::vec3 p = corner + 2.0f * glm::vec3(next(), next(), next());
                CellCornerCache before = kept;
                const ValueGradient cached = sample_value_gradient(v, p, kept);
                for (int slot = 0; slot < 8; ++slot)
                    fills += kept.by_parity[slot].base != before.by_parity[slot].base ? 1 : 0;
                ++samples;
                const ValueGradient fresh = sample_value_gradient(v, p);
                ASSERT_EQ(cached.value, fresh.value);
                ASSERT_EQ(cached.gradient.x, fresh.gradient.x);
                ASSERT_EQ(cached.gradient.y, fresh.gradient.y);
                ASSERT_EQ(cached.gradient.z, fresh.gradient.z);
            }
        }
        // One cell kept instead fills 1532 and 855 of 2400 on the first two grids.
        EXPECT_LT(fills, samples / 3) << fills << " of " << samples;
    }
}

// The trilinear field's own gradient: the value is sample_trilinear's bit for bit, a linear
// field's gradient is exact, and inside a cell it is the derivative of sample_trilinear.
TEST(Volume, TrilinearGradientIsTheDerivativeOfTheTrilinearField) {
    for (glm::ivec3 dims : {glm::ivec3(7, 6, 5), glm::ivec3(1, 4, 3), glm::ivec3(2, 1, 2)}) {
        const Volume v = wavy_volume(dims);
        UnitRandom next{4321u};
        int interior = 0;
        for (int k = 0; k < 500; ++k) {
            const glm::vec3 p = glm::vec3(next(), next(), next()) * (glm::vec3(dims) + 1.0f) - 0.5f;
            const ValueGradient vg = sample_trilinear_with_gradient(v, p);
            ASSERT_EQ(vg.value, sample_trilinear(v, p));
            // Central differences of the field itself, where p and p +- h stay in one cell.
            constexpr float h = 1e-2f;
            const glm::vec3 f = glm::fract(p);
            if (glm::any(glm::lessThan(f, glm::vec3(2 * h))) ||
                glm::any(glm::greaterThan(f, glm::vec3(1 - 2 * h))) ||
                glm::any(glm::lessThan(p, glm::vec3(0))) ||
                glm::any(glm::greaterThan(p, glm::vec3(dims - 1))))
                continue;
            ++interior;
            for (int a = 0; a < 3; ++a) {
                glm::vec3 step(0.0f);
                step[a] = h;
                const float numeric =
                    (sample_trilinear(v, p + step) - sample_trilinear(v, p - step)) / (2 * h);
                EXPECT_NEAR(vg.gradient[a], numeric, 0.02f) << "axis " << a;
            }
        }
        if (dims == glm::ivec3(7, 6, 5)) {
            EXPECT_GT(interior, 100);
        }
    }
    const Volume ramp = linear_ramp({6, 6, 6});
    for (const glm::vec3 p : {glm::vec3(2.3f, 3.7f, 1.2f), glm::vec3(0.0f, 0.0f, 5.0f)}) {
        const glm::vec3 g = sample_trilinear_with_gradient(ramp, p).gradient;
        EXPECT_NEAR(g.x, 2.0f, 1e-5f);
        EXPECT_NEAR(g.y, -3.0f, 1e-5f);
        EXPECT_NEAR(g.z, 0.5f, 1e-5f);
    }
}

// A hint for the caches: any point, even outside the volume or not finite, on any size of
// volume, is accepted (the sanitizers check the addresses it forms) and nothing read changes.
TEST(Volume, PrefetchCellAcceptsAnyPointAndChangesNothing) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const glm::vec3 points[] = {{0.0f, 0.0f, 0.0f},          {2.5f, 1.25f, 3.75f},
                                {-3.0f, 9.0f, 1e30f},        {kInf, -kInf, 0.0f},
                                {std::nanf(""), 1.0f, 1.0f}, {5.999f, 4.999f, 3.999f}};
    for (const glm::ivec3 dims : {glm::ivec3(6, 5, 4), glm::ivec3(1, 1, 1), glm::ivec3(2, 1, 1)}) {
        const Volume v = linear_ramp(dims);
        const std::vector<float> before = v.samples;
        for (const glm::vec3 p : points) {
            const float value = sample_trilinear(v, p); // finite: sampling clamps p
            prefetch_cell(v, p);
            EXPECT_EQ(sample_trilinear(v, p), value);
        }
        EXPECT_EQ(v.samples, before);
    }
    prefetch_cell(Volume{}, glm::vec3(1.0f)); // no samples: nothing to fetch
}

TEST(Volume, GaussianGradientOfLinearFieldAwayFromBorder) {
    const Volume v = linear_ramp({16, 16, 16});
    const GradientField field = gradient_field_gaussian(v, 1.5f);
    const glm::vec3 g = sample_trilinear(field, {7.5f, 8.0f, 8.25f});
    EXPECT_NEAR(g.x, 2.0f, 1e-3f);
    EXPECT_NEAR(g.y, -3.0f, 1e-3f);
    EXPECT_NEAR(g.z, 0.5f, 1e-3f);
}

TEST(Volume, GaussianGradientSmoothsNoise) {
    // On the noisy sphere the Gaussian gradient is closer to the true radial direction.
    const Phantom noisy = make_phantom("noisy-sphere", 32, 7);
    const GradientField field = gradient_field_gaussian(noisy.volume, 1.5f);
    const glm::vec3 c(15.5f);
    double central_error = 0, gaussian_error = 0;
    for (int i = 0; i < 200; ++i) {
        const float a = 0.1f * float(i), b = 0.37f * float(i);
        const glm::vec3 dir(std::cos(a) * std::sin(b), std::sin(a) * std::sin(b), std::cos(b));
        const glm::vec3 p = c + dir * 0.35f * 32.0f;
        // Inside positive: the gradient points inwards.
        central_error += glm::length(glm::normalize(gradient_central(noisy.volume, p)) + dir);
        gaussian_error += glm::length(glm::normalize(sample_trilinear(field, p)) + dir);
    }
    EXPECT_LT(gaussian_error, 0.5 * central_error);
}

TEST(Volume, WorldMappingRoundTrips) {
    Volume v = make_volume({4, 4, 4});
    v.spacing = {0.5f, 2.0f, 3.0f};
    v.origin = {10.0f, -5.0f, 1.0f};
    v.direction = glm::mat3(glm::vec3(0, 1, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 0, 1));
    const glm::vec3 w = index_to_world(v, {1.0f, 2.0f, 3.0f});
    EXPECT_NEAR(w.x, 10.0f - 4.0f, 1e-5f);
    EXPECT_NEAR(w.y, -5.0f + 0.5f, 1e-5f);
    EXPECT_NEAR(w.z, 1.0f + 9.0f, 1e-5f);
    const glm::vec3 back = world_to_index(v, w);
    EXPECT_NEAR(glm::distance(back, glm::vec3(1, 2, 3)), 0.0f, 1e-5f);
}

TEST(Volume, RejectsBadDimensions) {
    EXPECT_THROW(make_volume({0, 4, 4}), std::invalid_argument);
    EXPECT_THROW(make_volume({-1, 4, 4}), std::invalid_argument);
}

TEST(Segmentation, ThresholdRulesAndNaN) {
    Volume v = make_volume({4, 1, 1});
    v.samples = {0.0f, 1.0f, 2.0f, std::nanf("")};
    const Segmentation above = segment_threshold(v, 1.0f, InsideIs::Above);
    const Segmentation below = segment_threshold(v, 1.0f, InsideIs::Below);
    EXPECT_EQ(above.inside, (std::vector<std::uint8_t>{0, 1, 1, 0}));
    EXPECT_EQ(below.inside, (std::vector<std::uint8_t>{1, 1, 0, 0}));
}

TEST(Segmentation, Label) {
    Volume v = make_volume({5, 1, 1});
    v.samples = {0, 5, 5, 2, 5};
    EXPECT_EQ(segment_label(v, 5).count_inside(), 3u);
    EXPECT_EQ(segment_label(v, 2).count_inside(), 1u);
}

TEST(Phantom, DistanceMapsAndReferences) {
    for (const std::string& name : phantom_names()) {
        const Phantom p = make_phantom(name, 32);
        if (!is_teaching_phantom(name)) {
            EXPECT_EQ(p.volume.dims, glm::ivec3(32)) << name;
        }
        EXPECT_GT(segment_threshold(p.volume, p.iso).count_inside(), 0u) << name;
        EXPECT_LT(segment_threshold(p.volume, p.iso).count_inside(), p.volume.voxel_count())
            << name;
    }
    const Phantom sphere = make_phantom("sphere", 64);
    EXPECT_NEAR(sphere.reference_distance({31.5f + 22.4f, 31.5f, 31.5f}), 0.0f, 1e-4f);
    EXPECT_NEAR(sphere.reference_distance({31.5f, 31.5f, 31.5f}), 22.4f, 1e-4f);
    // The plane with normal (1, 2, 3) through the centre hits samples exactly.
    const Phantom plane = make_phantom("plane", 64);
    int exact = 0;
    for (float v : plane.volume.samples) exact += v == 0.0f;
    EXPECT_GT(exact, 100);
    const Phantom binary = make_phantom("binary-sphere", 16);
    for (float v : binary.volume.samples) EXPECT_TRUE(v == 0.0f || v == 1.0f);
    EXPECT_THROW(make_phantom("cube", 32), std::invalid_argument);
    EXPECT_THROW(make_phantom("sphere", 4), std::invalid_argument);
    EXPECT_EQ(phantom_spec_name("phantom:torus"), "torus");
    EXPECT_EQ(phantom_spec_name("torus.nrrd"), "");
}

TEST(Phantom, NoiseIsSeeded) {
    EXPECT_EQ(make_phantom("noisy-sphere", 16, 3).volume.samples,
              make_phantom("noisy-sphere", 16, 3).volume.samples);
    EXPECT_NE(make_phantom("noisy-sphere", 16, 3).volume.samples,
              make_phantom("noisy-sphere", 16, 4).volume.samples);
}

// The range skips NaN and both infinities wherever they fall (in a lane of four or in the tail
// after the last whole one), and is empty when no sample is finite.
TEST(VolumeStats, RangeSkipsNonFiniteSamplesAnywhere) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const float odd[] = {std::numeric_limits<float>::quiet_NaN(), kInf, -kInf};
    for (int size = 1; size <= 13; ++size)
        for (int at = 0; at < size; ++at)
            for (const float bad : odd) {
                Volume v = make_volume({size, 1, 1});
                for (int i = 0; i < size; ++i) v.samples[std::size_t(i)] = float(i * 3 % 7) - 2.0f;
                v.samples[std::size_t(at)] = bad;
                float lo = kInf, hi = -kInf;
                for (const float s : v.samples) {
                    if (!std::isfinite(s)) continue;
                    lo = std::min(lo, s);
                    hi = std::max(hi, s);
                }
                const ValueRange range = value_range(v);
                if (size == 1) {
                    EXPECT_EQ(range.min, 0.0f);
                    EXPECT_EQ(range.max, 0.0f);
                    continue;
                }
                EXPECT_EQ(range.min, lo) << size << " " << at;
                EXPECT_EQ(range.max, hi) << size << " " << at;
            }
    Volume none = make_volume({9, 1, 1}, std::numeric_limits<float>::quiet_NaN());
    none.samples[4] = kInf;
    const ValueRange empty = value_range(none);
    EXPECT_EQ(empty.min, 0.0f);
    EXPECT_EQ(empty.max, 0.0f);
}

// Merging neighbouring bins by a power of two gives the coarser histogram exactly, also for
// samples on the bins' edges (an integer ramp over a range of 2560 has one on every edge).
TEST(VolumeStats, MergedBinsEqualTheCoarserHistogram) {
    Volume v = make_volume({2561, 3, 1});
    for (std::size_t i = 0; i < v.samples.size(); ++i) v.samples[i] = float(i % 2561) - 1024.0f;
    const ValueRange range = value_range(v);
    const Histogram fine = make_histogram(v, 256, range);
    for (const int factor : {2, 4, 256}) {
        const Histogram merged = merge_bins(fine, factor);
        const Histogram direct = make_histogram(v, 256 / factor, range);
        EXPECT_EQ(merged.lo, direct.lo);
        EXPECT_EQ(merged.hi, direct.hi);
        EXPECT_EQ(merged.counts, direct.counts) << factor;
    }
    EXPECT_THROW(merge_bins(fine, 3), std::invalid_argument);
    EXPECT_THROW(merge_bins(fine, 0), std::invalid_argument);
}

// The range and the histogram equal a plain count, skip NaN and infinity, do not change with the
// thread count, and the histogram of a known range (a loader's) equals the one that measures it.
TEST(VolumeStats, RangeAndHistogramCountEveryFiniteSample) {
    Volume v = make_volume({257, 129, 137}); // 4.5 M samples: several chunks of each pass
    std::uint32_t state = 7u;
    for (float& s : v.samples) {
        state = state * 1664525u + 1013904223u;
        s = float(state >> 8) / float(1u << 24) * 3000.0f - 1000.0f;
    }
    v.samples[12345] = std::numeric_limits<float>::quiet_NaN();
    v.samples[4000000] = std::numeric_limits<float>::infinity();
    v.samples[3000001] = -std::numeric_limits<float>::infinity();
    v.samples[77] = -1500.0f;
    v.samples[4400000] = 2500.0f;
    Histogram serial;
    serial.lo = -1500.0f;
    serial.hi = 2500.0f;
    serial.counts.assign(64, 0);
    for (float s : v.samples)
        if (std::isfinite(s))
            ++serial.counts[std::min<std::size_t>(
                63, std::size_t((double(s) + 1500.0) / 4000.0 * 64.0))];
    for (const unsigned threads : {1u, 0u}) {
        const ThreadLimit limit(threads);
        const ValueRange range = value_range(v);
        EXPECT_EQ(range.min, -1500.0f);
        EXPECT_EQ(range.max, 2500.0f);
        const Histogram h = make_histogram(v, 64);
        EXPECT_EQ(h.lo, serial.lo);
        EXPECT_EQ(h.hi, serial.hi);
        EXPECT_EQ(h.counts, serial.counts);
        EXPECT_EQ(h.total(), v.samples.size() - 3);
        EXPECT_EQ(make_histogram(v, 64, range).counts, serial.counts);
        EXPECT_EQ(suggest_iso(v, range), suggest_iso(v));
    }
}
