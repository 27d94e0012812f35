// CellLists: the items (triangle ids) listed in each cell of a uniform grid, stored for the
// occupied cells only.
//
// The grids of the distance and self-intersection passes have up to a few million cells, and on
// a clinical mesh most of them are empty: an offset for every cell cost 16 MB a grid. Here each
// cell has a bit, each 64 cells a count of the occupied cells before them, and only the occupied
// cells an offset (a popcount finds a cell's place among them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "bit_planes.h"

namespace snert::detail {

class CellLists {
  public:
    // Lists every (item, cell) entry that for_each_entry(visit) passes to visit(item, cell),
    // cell < cells. for_each_entry is called three times (mark, count, fill) and must give the
    // same entries each time; items come out of items() in the order it gives them. Throws
    // std::invalid_argument, naming `what`, when there are 2^32 entries or more.
    template <class ForEachEntry>
    void build(std::size_t cells, ForEachEntry&& for_each_entry, const char* what) {
        occupied_.assign((cells + 63) / 64, 0);
        for_each_entry([&](std::uint32_t, std::size_t c) {
            occupied_[c >> 6] |= std::uint64_t(1) << (c & 63);
        });
        before_.resize(occupied_.size());
        std::size_t occupied_cells = 0;
        for (std::size_t w = 0; w < occupied_.size(); ++w) {
            if (occupied_cells >= std::numeric_limits<std::uint32_t>::max())
                throw std::invalid_argument(std::string(what) + ": too many grid cells");
            before_[w] = std::uint32_t(occupied_cells);
            occupied_cells += set_bits(occupied_[w]);
        }
        // Count, prefix sum, fill: start_[r + 1] runs as the fill position of occupied cell r.
        start_.assign(occupied_cells + 2, 0);
        std::size_t entries = 0;
        for_each_entry([&](std::uint32_t, std::size_t c) {
            ++start_[rank(c) + 2];
            ++entries;
        });
        if (entries >= std::numeric_limits<std::uint32_t>::max())
            throw std::invalid_argument(std::string(what) + ": mesh too large");
        for (std::size_t r = 2; r < start_.size(); ++r) start_[r] += start_[r - 1];
        items_.resize(entries);
        for_each_entry(
            [&](std::uint32_t item, std::size_t c) { items_[start_[rank(c) + 1]++] = item; });
        start_.pop_back();
    }

    // False for every cell before build().
    bool occupied(std::size_t c) const {
        return (c >> 6) < occupied_.size() && ((occupied_[c >> 6] >> (c & 63)) & 1) != 0;
    }

    std::span<const std::uint32_t> items(std::size_t c) const {
        if (!occupied(c)) return {};
        const std::size_t r = rank(c);
        return std::span<const std::uint32_t>(items_).subspan(start_[r], start_[r + 1] - start_[r]);
    }

  private:
    // The place of cell c among the occupied cells, in cell order.
    std::size_t rank(std::size_t c) const {
        const std::uint64_t below = occupied_[c >> 6] & ((std::uint64_t(1) << (c & 63)) - 1);
        return before_[c >> 6] + set_bits(below);
    }

    std::vector<std::uint64_t> occupied_; // a bit per cell
    std::vector<std::uint32_t> before_;   // occupied cells before each 64-cell word
    std::vector<std::uint32_t> start_;    // offsets into items_ of the occupied cells, and the end
    std::vector<std::uint32_t> items_;
};

// The items of a cell's list that pass `test`, kept in `kept` (reused storage) in list order and
// returned as a span of it. Without a branch: the grids' cheap tests (a sphere, a box) pass a
// few items in five or six, at random, and the mispredicted branches cost more than the tests;
// the callers then run their dearer tests on the few kept.
template <class Test>
std::span<const std::uint32_t> keep_passing(std::span<const std::uint32_t> items,
                                            std::vector<std::uint32_t>& kept, Test&& test) {
    if (kept.size() < items.size()) kept.resize(items.size());
    std::size_t count = 0;
    for (const std::uint32_t item : items) {
        kept[count] = item;
        count += test(item) ? 1 : 0;
    }
    return std::span<const std::uint32_t>(kept.data(), count);
}

} // namespace snert::detail
