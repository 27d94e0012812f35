// CellLists: the items of each occupied cell, in increasing order, across 64-cell words,
// whatever the thread count.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/cell_lists.h"
#include "core/parallel.h"

namespace snert::detail {
namespace {

std::vector<std::uint32_t> listed(const CellLists& lists, std::size_t cell) {
    const auto items = lists.items(cell);
    return {items.begin(), items.end()};
}

TEST(CellLists, ListsEachCellsItemsInIncreasingOrder) {
    // Cells in the first, a middle and the last word, and on word edges (63, 64, 127, 128).
    const std::vector<std::vector<std::size_t>> cells_of = {{63, 64}, {0},   {64}, {199},
                                                            {127},    {128}, {63}, {64}};
    CellLists lists;
    lists.build(
        200, cells_of.size(),
        [&](std::size_t first, std::size_t last, auto&& visit) {
            for (std::size_t item = first; item < last; ++item)
                for (const std::size_t cell : cells_of[item]) visit(std::uint32_t(item), cell);
        },
        "test");
    EXPECT_EQ(listed(lists, 63), (std::vector<std::uint32_t>{0, 6}));
    EXPECT_EQ(listed(lists, 64), (std::vector<std::uint32_t>{0, 2, 7}));
    EXPECT_EQ(listed(lists, 0), (std::vector<std::uint32_t>{1}));
    EXPECT_EQ(listed(lists, 127), (std::vector<std::uint32_t>{4}));
    EXPECT_EQ(listed(lists, 128), (std::vector<std::uint32_t>{5}));
    EXPECT_EQ(listed(lists, 199), (std::vector<std::uint32_t>{3}));
    std::vector<std::size_t> occupied;
    lists.for_each_occupied([&](std::size_t c) { occupied.push_back(c); });
    EXPECT_EQ(occupied, (std::vector<std::size_t>{0, 63, 64, 127, 128, 199}));
    // A range of cells: its ends within words and on their edges.
    const auto occupied_in = [&](std::size_t first, std::size_t last) {
        std::vector<std::size_t> found;
        lists.for_each_occupied_in(first, last, [&](std::size_t c) { found.push_back(c); });
        return found;
    };
    EXPECT_EQ(occupied_in(0, 200), occupied);
    EXPECT_EQ(occupied_in(63, 65), (std::vector<std::size_t>{63, 64}));
    EXPECT_EQ(occupied_in(1, 63), (std::vector<std::size_t>{}));
    EXPECT_EQ(occupied_in(64, 128), (std::vector<std::size_t>{64, 127}));
    EXPECT_EQ(occupied_in(100, 200), (std::vector<std::size_t>{127, 128, 199}));
    EXPECT_EQ(occupied_in(128, 129), (std::vector<std::size_t>{128}));
    EXPECT_EQ(occupied_in(199, 500), (std::vector<std::size_t>{199}));
    EXPECT_EQ(occupied_in(120, 120), (std::vector<std::size_t>{}));
    for (std::size_t c = 0; c < 200; ++c) {
        const bool used = c == 0 || c == 63 || c == 64 || c == 127 || c == 128 || c == 199;
        EXPECT_EQ(lists.occupied(c), used) << c;
        if (!used) {
            EXPECT_TRUE(lists.items(c).empty()) << c;
        }
    }
}

// Many chunks of items filled side by side by two threads: the same lists as one thread makes,
// each the items of its cell in increasing order.
TEST(CellLists, ThreadsFillTheSameLists) {
    constexpr std::size_t kItems = 200000, kCells = 7001;
    // Each item lands in one to three cells, scattered, some cells shared by many items.
    const auto for_each_entry_of = [](std::size_t first, std::size_t last, auto&& visit) {
        for (std::size_t item = first; item < last; ++item) {
            const std::size_t hash = item * 2654435761u;
            for (std::size_t k = 0; k <= hash % 3; ++k)
                visit(std::uint32_t(item), (hash / 7 + k * 13) % kCells);
        }
    };
    std::vector<std::vector<std::uint32_t>> expected(kCells);
    for_each_entry_of(
        0, kItems, [&](std::uint32_t item, std::size_t cell) { expected[cell].push_back(item); });
    for (const unsigned threads : {1u, 2u}) {
        const ThreadLimit limit(threads);
        CellLists lists;
        lists.build(kCells, kItems, for_each_entry_of, "test");
        std::size_t differing = 0;
        for (std::size_t c = 0; c < kCells; ++c) {
            differing += listed(lists, c) != expected[c];
            EXPECT_EQ(lists.occupied(c), !expected[c].empty()) << c;
        }
        EXPECT_EQ(differing, 0u) << threads << " threads";
    }
}

TEST(CellLists, EmptyAndUnbuiltListsHoldNothing) {
    CellLists unbuilt;
    EXPECT_FALSE(unbuilt.occupied(0));
    EXPECT_TRUE(unbuilt.items(5).empty());
    CellLists empty;
    empty.build(
        1, 0, [](std::size_t, std::size_t, auto&&) {}, "test");
    EXPECT_FALSE(empty.occupied(0));
    EXPECT_TRUE(empty.items(0).empty());
    CellLists unvisited;
    unvisited.build(
        100, 50, [](std::size_t, std::size_t, auto&&) {}, "test");
    EXPECT_FALSE(unvisited.occupied(99));
    int occupied = 0;
    unvisited.for_each_occupied([&](std::size_t) { ++occupied; });
    EXPECT_EQ(occupied, 0);
}

} // namespace
} // namespace snert::detail
