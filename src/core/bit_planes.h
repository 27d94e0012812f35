// Bit planes of a binary classification, shared by Marching Cubes and the surface net (internal
// to snert_core).
//
// One bit per sample, x fastest, rows of whole 64-bit words (padding bits are 0). A whole row
// of 64 cells is classified with a few word operations, so the empty bulk of a volume costs
// almost nothing and only cells the surface passes through are visited one by one (the
// "trimming" of flying edges, at word granularity).
//
// A cell is named by its lowest sample (x, y, z); its corner c sits at offset
// (c & 1, (c >> 1) & 1, (c >> 2) & 1), and its case is the 8-bit mask of inside corners, as in
// marching_cubes.h.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>

#include <glm/glm.hpp>

#include "huge_pages.h"

namespace snert::detail {

using Word = std::uint64_t;
inline constexpr int kWordBits = 64;

// The set bits of x, inline: on the baseline x86-64 target (no POPCNT instruction) std::popcount
// is a call into libgcc, made for every word counted.
inline std::size_t set_bits(Word x) {
    x -= (x >> 1) & 0x5555555555555555u;                              // 2-bit sums
    x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u); // 4-bit sums
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fu;                         // byte sums
    return std::size_t((x * 0x0101010101010101u) >> 56);              // all bytes, in the top one
}

// Bit x of the result is bit x + 1 of the row.
inline Word bits_above(const Word* row, int w, int words) {
    return (row[w] >> 1) | (w + 1 < words ? row[w + 1] << (kWordBits - 1) : Word(0));
}
// Bits x < count within word w.
inline Word bits_before(int count, int w) {
    const int first = w * kWordBits;
    if (count >= first + kWordBits) return ~Word(0);
    if (count <= first) return 0;
    return (Word(1) << (count - first)) - 1;
}
// 64 bytes of 0 or 1 -> one bit each. Eight at a time: the multiplication moves the low bit of
// byte k to bit 56 + k without carries into the top byte.
inline Word pack_bytes(const std::uint8_t* bytes) {
    Word bits = 0;
    for (int k = 0; k < 8; ++k) {
        Word eight = 0; // byte j at bits 8j; compilers turn this into one load
        for (int j = 0; j < 8; ++j) eight |= Word(bytes[8 * k + j]) << (8 * j);
        bits |= ((eight * 0x0102040810204080ull) >> 56) << (8 * k);
    }
    return bits;
}
// Bits x and x + 1 of a row as a 2-bit number (x + 1 must be a sample).
inline unsigned bit_pair(const Word* row, int x) {
    const int w = x / kWordBits, b = x % kWordBits;
    Word v = row[w] >> b;
    if (b == kWordBits - 1) v |= row[w + 1] << 1;
    return unsigned(v & 3u);
}
// Calls f(x) for each set bit of word w, in increasing x.
template <class F> inline void for_each_bit(Word bits, int w, F&& f) {
    while (bits != 0) {
        f(w * kWordBits + std::countr_zero(bits));
        bits &= bits - 1;
    }
}

// The four sample rows around a row of cells: (y, z), (y + 1, z), (y, z + 1), (y + 1, z + 1)
// give corners 0-1, 2-3, 4-5, 6-7.
struct CellRows {
    const Word* r[4];
    // The case (8-bit corner mask) of cell x.
    unsigned mask(int x) const {
        return bit_pair(r[0], x) | bit_pair(r[1], x) << 2 | bit_pair(r[2], x) << 4 |
               bit_pair(r[3], x) << 6;
    }
};

class BitVolume {
  public:
    BitVolume() = default;
    // Words are left uninitialised: every row must be set (set_row) before it is read.
    explicit BitVolume(glm::ivec3 dims)
        : dims_(dims), words_per_row_((dims.x + kWordBits - 1) / kWordBits),
          words_(std::size_t(words_per_row_) * std::size_t(dims.y) * std::size_t(dims.z)) {}

    glm::ivec3 dims() const { return dims_; }
    int words_per_row() const { return words_per_row_; }
    Word* row(int y, int z) { return words_.get() + offset(y, z); }
    const Word* row(int y, int z) const { return words_.get() + offset(y, z); }

    // Sets row (y, z) from inside(x) for x in [0, dims.x). Bytes first (a loop that vectorises
    // when inside is simple), then bits.
    template <class Inside> void set_row(int y, int z, const Inside& inside) {
        alignas(64) std::uint8_t in[kWordBits];
        Word* out = row(y, z);
        for (int w = 0; w < words_per_row_; ++w) {
            const int first = w * kWordBits, n = std::min(kWordBits, dims_.x - first);
            if (n == kWordBits) {
                for (int i = 0; i < kWordBits; ++i) in[i] = inside(first + i) ? 1 : 0;
            } else {
                for (int i = 0; i < kWordBits; ++i) in[i] = i < n && inside(first + i) ? 1 : 0;
            }
            out[w] = pack_bytes(in);
        }
    }

    // Rows of cell row (y, z); y + 1 and z + 1 must be samples.
    CellRows cell_rows(int y, int z) const {
        return {{row(y, z), row(y + 1, z), row(y, z + 1), row(y + 1, z + 1)}};
    }

    // Cells of word w of a row of cells that the surface passes through (corners not all
    // equal).
    Word active_cells(const CellRows& rows, int w) const {
        const auto any = [&](int i) {
            return rows.r[0][i] | rows.r[1][i] | rows.r[2][i] | rows.r[3][i];
        };
        const auto all = [&](int i) {
            return rows.r[0][i] & rows.r[1][i] & rows.r[2][i] & rows.r[3][i];
        };
        const bool more = w + 1 < words_per_row_;
        const Word any_w = any(w), all_w = all(w);
        const Word any_pair = any_w | (any_w >> 1) | (more ? any(w + 1) << (kWordBits - 1) : 0);
        const Word all_pair = all_w & ((all_w >> 1) | (more ? all(w + 1) << (kWordBits - 1) : 0));
        return any_pair & ~all_pair & bits_before(dims_.x - 1, w);
    }

    // Calls visit(x, case) for the surface cells of cell row (y, z), in increasing x.
    template <class Visit> void for_each_surface_cell(int y, int z, Visit&& visit) const {
        const CellRows rows = cell_rows(y, z);
        for (int w = 0; w < words_per_row_; ++w)
            for_each_bit(active_cells(rows, w), w, [&](int x) { visit(x, rows.mask(x)); });
    }

  private:
    std::size_t offset(int y, int z) const {
        return (std::size_t(z) * std::size_t(dims_.y) + std::size_t(y)) *
               std::size_t(words_per_row_);
    }
    glm::ivec3 dims_{0};
    int words_per_row_ = 0;
    ScratchArray<Word> words_;
};

// Sets row (y, z) of `bits` from the grey samples `v` of that row against `iso`: inside where
// v >= iso (`above`) or v <= iso. NaN compares false both ways, so it is outside for either rule,
// as segment_threshold() has it.
inline void set_threshold_row(BitVolume& bits, int y, int z, const float* v, float iso,
                              bool above) {
    if (above)
        bits.set_row(y, z, [&](int x) { return v[x] >= iso; });
    else
        bits.set_row(y, z, [&](int x) { return v[x] <= iso; });
}

} // namespace snert::detail
