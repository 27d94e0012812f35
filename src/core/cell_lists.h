// CellLists: the items (triangle ids) listed in each cell of a uniform grid, stored for the
// occupied cells only.
//
// The grids of the distance and self-intersection passes have up to a few million cells, and on
// a clinical mesh most of them are empty: an offset for every cell cost 16 MB a grid. Here each
// cell has a bit, each 64 cells a count of the occupied cells before them, and only the occupied
// cells an offset (a popcount finds a cell's place among them). The lists are built on every
// thread, then each sorted: the same lists whatever the thread count.
#pragma once

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "bit_planes.h"
#include "huge_pages.h"
#include "parallel.h"

namespace snert::detail {

class CellLists {
  public:
    // Lists every (item, cell) entry that for_each_entry_of(first, last, visit) passes to
    // visit(item, cell), cell < cells, for the items [first, last) of 0 .. items - 1; it is called
    // three times for each chunk of items (mark, count, fill), on every thread, and must give the
    // same entries each time. A cell's items come out in increasing order. Throws
    // std::invalid_argument, naming `what`, when there are 2^32 entries or more.
    template <class ForEachEntryOf>
    void build(std::size_t cells, std::size_t items, ForEachEntryOf&& for_each_entry_of,
               const char* what) {
        constexpr std::size_t kChunk = std::size_t(1) << 14;
        occupied_.assign((cells + 63) / 64, 0);
        for_each_chunk(items, kChunk, [&](std::size_t, std::size_t first, std::size_t last) {
            for_each_entry_of(first, last, [&](std::uint32_t, std::size_t c) {
                const std::uint64_t bit = std::uint64_t(1) << (c & 63);
                std::atomic_ref<std::uint64_t> word(occupied_[c >> 6]);
                if ((word.load(std::memory_order_relaxed) & bit) == 0)
                    word.fetch_or(bit, std::memory_order_relaxed);
            });
        });
        rank_occupied_cells(what);
        // Count, prefix sum, fill: start_[r + 1] runs as the fill position of occupied cell r.
        std::vector<std::size_t> chunk_entries(chunk_count(items, kChunk), 0);
        for_each_chunk(items, kChunk, [&](std::size_t chunk, std::size_t first, std::size_t last) {
            std::size_t entries = 0;
            for_each_entry_of(first, last, [&](std::uint32_t, std::size_t c) {
                std::atomic_ref<std::uint32_t>(start_[rank(c) + 2])
                    .fetch_add(1, std::memory_order_relaxed);
                ++entries;
            });
            chunk_entries[chunk] = entries;
        });
        std::size_t entries = 0;
        for (const std::size_t n : chunk_entries) entries += n;
        if (entries >= std::numeric_limits<std::uint32_t>::max())
            throw std::invalid_argument(std::string(what) + ": mesh too large");
        for (std::size_t r = 2; r < start_.size(); ++r) start_[r] += start_[r - 1];
        // On huge pages, as start_: a clinical mesh's lists (10 MB) faulted 4 KiB at a time here,
        // on one thread, before the threads filled them.
        assign_on_huge_pages(items_, entries);
        for_each_chunk(items, kChunk, [&](std::size_t, std::size_t first, std::size_t last) {
            for_each_entry_of(first, last, [&](std::uint32_t item, std::size_t c) {
                const std::uint32_t slot = std::atomic_ref<std::uint32_t>(start_[rank(c) + 1])
                                               .fetch_add(1, std::memory_order_relaxed);
                items_[slot] = item;
            });
        });
        start_.pop_back();
        // The threads filled the lists side by side: each put back in increasing order (a few
        // items a cell), so the lists do not depend on the threads.
        const std::size_t lists = start_.size() - 1;
        for_each_chunk(lists, kChunk, [&](std::size_t, std::size_t first, std::size_t last) {
            for (std::size_t r = first; r < last; ++r)
                sort_list(items_.data() + start_[r], items_.data() + start_[r + 1]);
        });
    }

    // False for every cell before build().
    bool occupied(std::size_t c) const {
        return (c >> 6) < occupied_.size() && ((occupied_[c >> 6] >> (c & 63)) & 1) != 0;
    }

    // Calls f(c) for every occupied cell c, in increasing order.
    template <class F> void for_each_occupied(F&& f) const {
        for (std::size_t w = 0; w < occupied_.size(); ++w)
            for (std::uint64_t bits = occupied_[w]; bits != 0; bits &= bits - 1)
                f(w * 64 + std::size_t(std::countr_zero(bits)));
    }

    // Calls f(c) for every occupied cell c in [first, last), in increasing order: a word of 64
    // empty cells at a time.
    template <class F> void for_each_occupied_in(std::size_t first, std::size_t last, F&& f) const {
        last = std::min(last, occupied_.size() * 64);
        for (std::size_t w = first >> 6; w < (last + 63) >> 6; ++w) {
            std::uint64_t bits = occupied_[w];
            if (w == first >> 6) bits &= ~std::uint64_t(0) << (first & 63);
            if (w == (last - 1) >> 6 && (last & 63) != 0)
                bits &= ~(~std::uint64_t(0) << (last & 63));
            for (; bits != 0; bits &= bits - 1) f(w * 64 + std::size_t(std::countr_zero(bits)));
        }
    }

    std::span<const std::uint32_t> items(std::size_t c) const {
        if (!occupied(c)) return {};
        const std::size_t r = rank(c);
        return std::span<const std::uint32_t>(items_).subspan(start_[r], start_[r + 1] - start_[r]);
    }

  private:
    // before_ from occupied_, and start_ zeroed for the counts.
    void rank_occupied_cells(const char* what) {
        before_.resize(occupied_.size());
        std::size_t occupied_cells = 0;
        for (std::size_t w = 0; w < occupied_.size(); ++w) {
            if (occupied_cells >= std::numeric_limits<std::uint32_t>::max())
                throw std::invalid_argument(std::string(what) + ": too many grid cells");
            before_[w] = std::uint32_t(occupied_cells);
            occupied_cells += set_bits(occupied_[w]);
        }
        assign_on_huge_pages(start_, occupied_cells + 2, std::uint32_t(0));
    }

    // Insertion sort for the few items a list mostly holds; std::sort for a long one (a mesh of
    // tiny triangles beside a few large ones has cells of many), which would be quadratic so.
    static void sort_list(std::uint32_t* first, std::uint32_t* last) {
        if (last - first > 32) {
            std::sort(first, last);
            return;
        }
        for (std::uint32_t* i = first + (first != last ? 1 : 0); i < last; ++i) {
            const std::uint32_t item = *i;
            std::uint32_t* j = i;
            for (; j > first && *(j - 1) > item; --j) *j = *(j - 1);
            *j = item;
        }
    }

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

} // namespace snert::detail
