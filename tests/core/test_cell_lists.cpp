// CellLists: the items of each occupied cell, in the order given, across 64-cell words.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/cell_lists.h"

namespace snert::detail {
namespace {

std::vector<std::uint32_t> listed(const CellLists& lists, std::size_t cell) {
    const auto items = lists.items(cell);
    return {items.begin(), items.end()};
}

TEST(CellLists, ListsEachCellsItemsInTheOrderGiven) {
    // Cells in the first, a middle and the last word, and on word edges (63, 64, 127, 128).
    const std::vector<std::pair<std::uint32_t, std::size_t>> entries = {
        {0, 63}, {0, 64}, {1, 0}, {2, 64}, {3, 199}, {4, 127}, {5, 128}, {6, 63}, {7, 64}};
    CellLists lists;
    lists.build(
        200,
        [&](auto&& visit) {
            for (const auto& [item, cell] : entries) visit(item, cell);
        },
        "test");
    EXPECT_EQ(listed(lists, 63), (std::vector<std::uint32_t>{0, 6}));
    EXPECT_EQ(listed(lists, 64), (std::vector<std::uint32_t>{0, 2, 7}));
    EXPECT_EQ(listed(lists, 0), (std::vector<std::uint32_t>{1}));
    EXPECT_EQ(listed(lists, 127), (std::vector<std::uint32_t>{4}));
    EXPECT_EQ(listed(lists, 128), (std::vector<std::uint32_t>{5}));
    EXPECT_EQ(listed(lists, 199), (std::vector<std::uint32_t>{3}));
    for (std::size_t c = 0; c < 200; ++c) {
        const bool used = c == 0 || c == 63 || c == 64 || c == 127 || c == 128 || c == 199;
        EXPECT_EQ(lists.occupied(c), used) << c;
        if (!used) {
            EXPECT_TRUE(lists.items(c).empty()) << c;
        }
    }
}

TEST(CellLists, EmptyAndUnbuiltListsHoldNothing) {
    CellLists unbuilt;
    EXPECT_FALSE(unbuilt.occupied(0));
    EXPECT_TRUE(unbuilt.items(5).empty());
    CellLists empty;
    empty.build(
        1, [](auto&&) {}, "test");
    EXPECT_FALSE(empty.occupied(0));
    EXPECT_TRUE(empty.items(0).empty());
}

} // namespace
} // namespace snert::detail
