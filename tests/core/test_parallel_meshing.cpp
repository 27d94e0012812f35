// Marching Cubes, the segmentation and the net run their passes over fixed chunks of slabs in
// parallel (parallel.h); their output must not depend on the number of threads.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <random>
#include <stop_token>
#include <vector>

#include "core/marching_cubes.h"
#include "core/parallel.h"
#include "core/phantom.h"
#include "core/surface_net.h"

using namespace snert;

namespace {

// Noise with a smooth trend: many ambiguous faces, split links and border pieces, over more
// slabs than one chunk holds.
Volume noisy_volume(glm::ivec3 dims, unsigned seed) {
    Volume v;
    v.dims = dims;
    v.samples.resize(std::size_t(dims.x) * dims.y * dims.z);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> noise(-1.0f, 1.0f);
    std::size_t i = 0;
    for (int z = 0; z < dims.z; ++z)
        for (int y = 0; y < dims.y; ++y)
            for (int x = 0; x < dims.x; ++x)
                v.samples[i++] = noise(rng) + 0.05f * float(x - dims.x / 2);
    return v;
}

// Volumes of several shapes: a phantom, noise, and noise with x wider than one bit word and
// samples exactly at the iso value.
std::vector<Volume> test_volumes() {
    std::vector<Volume> volumes;
    volumes.push_back(make_phantom("torus", 48).volume);
    volumes.push_back(noisy_volume({23, 19, 41}, 1));
    Volume wide = noisy_volume({131, 7, 29}, 2);
    for (std::size_t k = 0; k < wide.samples.size(); k += 7) wide.samples[k] = 0.0f;
    volumes.push_back(std::move(wide));
    return volumes;
}

template <class F> auto with_threads(unsigned threads, F&& f) {
    ThreadLimit limit(threads);
    return f();
}

} // namespace

TEST(ParallelMeshing, MarchingCubesIsTheSameForAnyThreadCount) {
    for (const Volume& v : test_volumes())
        for (const InsideIs inside : {InsideIs::Above, InsideIs::Below}) {
            const MarchingCubesOptions options{0.0f, inside};
            const Mesh one = with_threads(1, [&] { return marching_cubes(v, options); });
            ASSERT_GT(one.triangle_count(), 0u);
            for (const unsigned threads : {2u, 0u}) {
                const Mesh many = with_threads(threads, [&] { return marching_cubes(v, options); });
                EXPECT_EQ(many.positions, one.positions) << threads;
                EXPECT_EQ(many.indices, one.indices) << threads;
            }
        }
}

TEST(ParallelMeshing, SegmentationIsTheSameForAnyThreadCount) {
    Volume v = noisy_volume({128, 96, 96}, 3); // more samples than one chunk (2^20)
    v.samples[17] = std::nanf("");
    for (const InsideIs inside : {InsideIs::Above, InsideIs::Below}) {
        const Segmentation one =
            with_threads(1, [&] { return segment_threshold(v, 0.0f, inside); });
        const Segmentation many =
            with_threads(0, [&] { return segment_threshold(v, 0.0f, inside); });
        EXPECT_EQ(many.inside, one.inside);
        EXPECT_EQ(one.inside[17], 0) << "NaN is outside";
        for (std::size_t i = 0; i < v.samples.size(); i += 101)
            EXPECT_EQ(one.inside[i] != 0, is_inside(v.samples[i], 0.0f, inside)) << i;
    }
}

TEST(ParallelMeshing, SurfaceNetIsTheSameForAnyThreadCount) {
    for (const Volume& v : test_volumes()) {
        const Segmentation s = segment_threshold(v, 0.0f);
        const SurfaceNet one = with_threads(1, [&] { return build_surface_net(s); });
        ASSERT_GT(one.node_count(), 0u);
        for (const unsigned threads : {2u, 0u}) {
            const SurfaceNet many = with_threads(threads, [&] { return build_surface_net(s); });
            EXPECT_EQ(many.cells, one.cells);
            EXPECT_EQ(many.pieces, one.pieces);
            EXPECT_EQ(many.regions, one.regions);
            EXPECT_EQ(many.positions, one.positions);
            EXPECT_EQ(many.link_offsets, one.link_offsets);
            EXPECT_EQ(many.links, one.links);
            EXPECT_EQ(many.quads, one.quads);
            EXPECT_EQ(many.triangles, one.triangles);
            EXPECT_EQ(many.star_offsets, one.star_offsets);
            EXPECT_EQ(many.star, one.star);
        }
    }
}

// Built from the grey samples, the net is the one of their threshold, node for node, for
// either rule, with samples at the iso and NaN (outside for both), on any thread count.
TEST(ParallelMeshing, NetFromTheSamplesEqualsTheNetOfTheirThreshold) {
    for (Volume v : test_volumes()) {
        for (std::size_t k = 3; k < v.samples.size(); k += 101)
            v.samples[k] = std::numeric_limits<float>::quiet_NaN();
        for (const InsideIs rule : {InsideIs::Above, InsideIs::Below}) {
            const SurfaceNet expected = build_surface_net(segment_threshold(v, 0.0f, rule));
            ASSERT_GT(expected.node_count(), 0u);
            for (const unsigned threads : {1u, 0u}) {
                const SurfaceNet net =
                    with_threads(threads, [&] { return build_surface_net(v, 0.0f, rule); });
                EXPECT_EQ(net.cell_dims, expected.cell_dims);
                EXPECT_EQ(net.cells, expected.cells);
                EXPECT_EQ(net.pieces, expected.pieces);
                EXPECT_EQ(net.regions, expected.regions);
                EXPECT_EQ(net.positions, expected.positions);
                EXPECT_EQ(net.link_offsets, expected.link_offsets);
                EXPECT_EQ(net.links, expected.links);
                EXPECT_EQ(net.quads, expected.quads);
                EXPECT_EQ(net.triangles, expected.triangles);
                EXPECT_EQ(net.star_offsets, expected.star_offsets);
                EXPECT_EQ(net.star, expected.star);
            }
        }
    }
    Volume short_samples = make_volume({4, 4, 4});
    short_samples.samples.pop_back();
    EXPECT_THROW(build_surface_net(short_samples, 0.0f, InsideIs::Above), std::invalid_argument);
}

TEST(ParallelMeshing, NetHasSplitLinksInTheTestVolumes) {
    // The invariance above covers link nodes only if the volumes make some.
    const Segmentation s = segment_threshold(test_volumes()[1], 0.0f);
    const SurfaceNet net = build_surface_net(s);
    std::size_t link_nodes = 0;
    for (const std::uint8_t p : net.pieces) link_nodes += p == kLinkNodePiece ? 1 : 0;
    EXPECT_GT(link_nodes, 0u);
}

TEST(ParallelMeshing, ProgressIsSerialAndIncreasingOnManyThreads) {
    const Volume v = noisy_volume({40, 40, 64}, 4);
    for (const int which : {0, 1}) {
        std::vector<float> reported;
        Progress progress;
        progress.report = [&](float f) { reported.push_back(f); }; // not thread-safe on purpose
        ThreadLimit limit(0);
        if (which == 0)
            marching_cubes(v, {}, progress);
        else
            build_surface_net(segment_threshold(v, 0.0f), progress);
        ASSERT_GE(reported.size(), 64u);
        EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
        EXPECT_EQ(reported.back(), 1.0f);
    }
}

TEST(ParallelMeshing, CancelsFromAnyThread) {
    const Volume v = noisy_volume({40, 40, 64}, 5);
    const Segmentation s = segment_threshold(v, 0.0f);
    for (const int after : {1, 70, 150}) { // during each pass
        std::stop_source stop;
        int calls = 0;
        Progress progress;
        progress.stop = stop.get_token();
        progress.report = [&](float) {
            if (++calls == after) stop.request_stop();
        };
        ThreadLimit limit(0);
        EXPECT_THROW(marching_cubes(v, {}, progress), Cancelled) << after;
        calls = 0;
        stop = std::stop_source();
        progress.stop = stop.get_token();
        EXPECT_THROW(build_surface_net(s, progress), Cancelled) << after;
    }
}
