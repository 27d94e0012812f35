// Slices: the samples of a plane, a mesh's cross-section, the net's layer, window/level.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "core/marching_cubes.h"
#include "core/phantom.h"
#include "core/segmentation.h"
#include "core/slice.h"
#include "core/surface_net.h"
#include "core/window_level.h"

using namespace snert;

TEST(Slice, SamplesOfEachAxis) {
    Volume v = make_volume({4, 5, 6});
    for (std::size_t i = 0; i < v.samples.size(); ++i) v.samples[i] = float(i);
    const Slice axial = extract_slice(v, {SliceAxis::Axial, 2});
    EXPECT_EQ(axial.size, glm::ivec2(4, 5));
    EXPECT_EQ(axial.at(3, 4), v.at(3, 4, 2));
    const Slice coronal = extract_slice(v, {SliceAxis::Coronal, 1});
    EXPECT_EQ(coronal.size, glm::ivec2(4, 6));
    EXPECT_EQ(coronal.at(2, 5), v.at(2, 1, 5));
    const Slice sagittal = extract_slice(v, {SliceAxis::Sagittal, 3});
    EXPECT_EQ(sagittal.size, glm::ivec2(5, 6));
    EXPECT_EQ(sagittal.at(4, 1), v.at(3, 4, 1));
    EXPECT_EQ(slice_count(v, SliceAxis::Sagittal), 4);
    EXPECT_THROW(extract_slice(v, {SliceAxis::Axial, 6}), std::invalid_argument);
    EXPECT_THROW(extract_slice(v, {SliceAxis::Axial, -1}), std::invalid_argument);
    // Slice and index coordinates map back and forth.
    const SlicePlane plane{SliceAxis::Coronal, 3};
    EXPECT_EQ(slice_to_index(plane, {1.5f, 2.5f}), glm::vec3(1.5f, 3.0f, 2.5f));
    EXPECT_EQ(index_to_slice(SliceAxis::Coronal, {1.5f, 3.0f, 2.5f}), glm::vec2(1.5f, 2.5f));
    EXPECT_EQ(parse_name<SliceAxis>("sagittal"), SliceAxis::Sagittal);
    const Segmentation seg = segment_threshold(v, 60.0f);
    const std::vector<std::uint8_t> mask =
        extract_slice_mask(seg.inside, v.dims, {SliceAxis::Axial, 2});
    EXPECT_EQ(mask[0], v.at(0, 0, 2) >= 60.0f);
    EXPECT_EQ(mask.size(), 20u);
}

// A slice's own samples thresholded give the flags of the thresholded volume's slice, NaN
// outside, for either rule and every axis (the slice view thresholds only what it shows); with a
// mask, the mask's flags there, whatever the grey values say.
TEST(Slice, ThresholdedSliceIsTheSegmentationsSlice) {
    Volume v = make_volume({7, 5, 6});
    for (std::size_t i = 0; i < v.samples.size(); ++i) v.samples[i] = float((i * 37) % 101);
    v.samples[v.index(2, 3, 4)] = std::numeric_limits<float>::quiet_NaN();
    v.samples[v.index(5, 1, 2)] = 50.0f; // exactly at the iso: inside for either rule
    for (const InsideIs rule : {InsideIs::Above, InsideIs::Below}) {
        const Segmentation seg = segment_threshold(v, 50.0f, rule);
        for (const SliceAxis axis : {SliceAxis::Axial, SliceAxis::Coronal, SliceAxis::Sagittal})
            for (int index = 0; index < slice_count(v, axis); ++index) {
                const SlicePlane plane{axis, index};
                EXPECT_EQ(slice_inside(extract_slice(v, plane), nullptr, 50.0f, rule),
                          extract_slice_mask(seg.inside, v.dims, plane))
                    << name_of(axis) << " " << index;
                EXPECT_EQ(slice_inside(extract_slice(v, plane), &seg, 200.0f, InsideIs::Above),
                          extract_slice_mask(seg.inside, v.dims, plane))
                    << "the mask's flags, " << name_of(axis) << " " << index;
            }
    }
    const std::vector<std::uint8_t> axial =
        slice_inside(extract_slice(v, {SliceAxis::Axial, 4}), nullptr, 50.0f, InsideIs::Below);
    EXPECT_EQ(axial[3 * 7 + 2], 0) << "NaN is outside";
}

TEST(Slice, CrossSectionOfTheSmallSphereIsItsCircle) {
    const Phantom p = make_phantom("small-sphere");
    const Mesh mc = marching_cubes(p.volume, {p.iso, InsideIs::Above});
    const SlicePlane plane{SliceAxis::Axial, 5};
    const std::vector<Segment2> cut = mesh_cross_section(mc, plane);
    ASSERT_GT(cut.size(), 12u);
    // Centre (5.6, 5.45, 5.3), radius 4: the circle in z = 5 has radius sqrt(16 - 0.09).
    const float radius = std::sqrt(16.0f - 0.09f);
    std::map<std::pair<long, long>, int> ends;
    for (const Segment2& s : cut)
        for (const glm::vec2 e : {s.a, s.b}) {
            EXPECT_NEAR(glm::length(e - glm::vec2(5.6f, 5.45f)), radius, 0.15f);
            ++ends[{std::lround(e.x * 1e4f), std::lround(e.y * 1e4f)}];
        }
    // A closed curve: every end point is shared by two segments.
    for (const auto& [point, count] : ends) EXPECT_EQ(count, 2);
    // The same curve from the mesh in world units on a grid with spacing, origin and a
    // mirrored axis, mapped back to index space.
    Volume grid = p.volume;
    grid.spacing = {0.8f, 1.0f, 2.5f};
    grid.origin = {10.0f, -4.0f, 3.0f};
    grid.direction = glm::mat3(glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, 1));
    Mesh world = mc;
    for (glm::vec3& q : world.positions) q = index_to_world(grid, q);
    const std::vector<Segment2> again = mesh_cross_section(world, grid, plane);
    ASSERT_EQ(again.size(), cut.size());
    for (std::size_t i = 0; i < cut.size(); ++i) {
        EXPECT_LT(glm::length(again[i].a - cut[i].a), 1e-4f);
        EXPECT_LT(glm::length(again[i].b - cut[i].b), 1e-4f);
    }
}

TEST(Slice, NetLayerNodesLinksAndSurfaceCells) {
    const Phantom p = make_phantom("small-sphere");
    const SurfaceNet net = build_surface_net(segment_threshold(p.volume, p.iso));
    const SliceNet s = net_in_slice(net, {SliceAxis::Coronal, 5});
    EXPECT_EQ(s.layer, 5);
    ASSERT_GT(s.nodes.size(), 12u);
    std::set<std::uint32_t> nodes(s.nodes.begin(), s.nodes.end());
    for (const std::uint32_t i : s.nodes) EXPECT_EQ(net.cells[i].y, 5);
    // In the layer the net is a closed ring: each node has two links in it.
    std::map<std::uint32_t, int> degree;
    for (const auto& l : s.links) {
        EXPECT_TRUE(nodes.count(l[0]) && nodes.count(l[1]));
        ++degree[l[0]], ++degree[l[1]];
    }
    for (const std::uint32_t i : s.nodes) EXPECT_EQ(degree[i], 2) << i;
    EXPECT_EQ(s.surface_cells.size(), s.nodes.size()); // one piece per cell on a sphere
    // The last sample plane uses the last layer of cells.
    EXPECT_EQ(net_in_slice(net, {SliceAxis::Axial, 11}).layer, 10);
}

// The MR preset's percentiles are the signal's values of those ranks, exactly as ordering a copy
// of the signal (finite, non-zero) gives them: with NaN, infinities, zeros, repeats, negative
// values and most samples in a narrow band (many in the percentiles' bins).
TEST(WindowLevel, MrPercentilesAreTheSignalsRanks) {
    Volume v = make_volume({40, 30, 20});
    std::uint32_t state = 12345;
    for (float& x : v.samples) {
        state = state * 1664525u + 1013904223u;
        const std::uint32_t r = state >> 8;
        x = r % 7 == 0 ? 0.0f : r % 11 == 0 ? -float(r % 300) : 100.0f + float(r % 100000) * 1e-5f;
    }
    v.samples[3] = std::numeric_limits<float>::quiet_NaN();
    v.samples[5] = std::numeric_limits<float>::infinity();
    v.samples[7] = 5000.0f;
    std::vector<float> signal;
    for (const float x : v.samples)
        if (std::isfinite(x) && x != 0.0f) signal.push_back(x);
    std::sort(signal.begin(), signal.end());
    const auto at = [&](double q) { return signal[std::size_t(q * double(signal.size() - 1))]; };
    const WindowLevel mr = window_preset(WindowPreset::Mr, v);
    const float lo = at(0.01), hi = at(0.99);
    EXPECT_EQ(mr, (WindowLevel{hi - lo, 0.5f * (lo + hi)}));
    // No signal: the full range.
    Volume zeros = make_volume({4, 4, 4});
    EXPECT_EQ(window_preset(WindowPreset::Mr, zeros), window_preset(WindowPreset::Full, zeros));
}

TEST(WindowLevel, GreysAndPresets) {
    const WindowLevel wl{100.0f, 50.0f};
    EXPECT_EQ(window_grey(0.0f, wl), 0);
    EXPECT_EQ(window_grey(100.0f, wl), 255);
    EXPECT_EQ(window_grey(50.0f, wl), 128);
    EXPECT_EQ(window_grey(-1e9f, wl), 0);
    Volume v = make_volume({10, 10, 1});
    for (std::size_t i = 0; i < 100; ++i) v.samples[i] = float(i); // 0 = background
    EXPECT_EQ(window_preset(WindowPreset::CtBone, v), (WindowLevel{2000.0f, 400.0f}));
    EXPECT_EQ(window_preset(WindowPreset::Full, v), (WindowLevel{99.0f, 49.5f}));
    const WindowLevel mr = window_preset(WindowPreset::Mr, v);
    EXPECT_NEAR(mr.level - 0.5f * mr.window, 1.0f, 1e-4f); // 1st percentile of 1..99
    EXPECT_NEAR(mr.level + 0.5f * mr.window, 98.0f, 1e-4f);
    // Auto: MR where nothing is negative, soft tissue on Hounsfield units, else everything.
    EXPECT_EQ(window_preset(WindowPreset::Auto, v), mr);
    v.samples[0] = -1000.0f;
    v.samples[1] = 1200.0f;
    EXPECT_EQ(window_preset(WindowPreset::Auto, v), (WindowLevel{400.0f, 40.0f}));
    v.samples[1] = 1.0f;
    EXPECT_EQ(window_preset(WindowPreset::Auto, v), window_preset(WindowPreset::Full, v));
    Slice s;
    s.size = {2, 1};
    s.values = {0.0f, 100.0f};
    const std::vector<std::uint8_t> mask = {1, 0};
    const std::vector<std::uint8_t> px = slice_pixels(s, wl, mask, {1, 0, 0}, 0.5f);
    EXPECT_EQ(px, (std::vector<std::uint8_t>{128, 0, 0, 255, 255, 255, 255, 255}));
}
