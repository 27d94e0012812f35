// Which of a mesh's indices changed since an earlier mesh of the same topology. Header-only and
// GL-free, so the app's worker can find them off the UI thread without linking the renderer.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace snert::render {

// A run [first, end) of a mesh's indices.
struct IndexRun {
    std::size_t first = 0, end = 0;
    bool operator==(const IndexRun&) const = default;
};

// The runs of `indices` that differ from `previous` (the same size), found a block of 128
// triangles at a time: a relaxation step splits a few quads along their other diagonal, scattered
// over the mesh. Throws std::invalid_argument when the sizes differ.
inline std::vector<IndexRun> changed_index_runs(std::span<const std::uint32_t> indices,
                                                std::span<const std::uint32_t> previous) {
    if (indices.size() != previous.size())
        throw std::invalid_argument("changed_index_runs: " + std::to_string(indices.size()) +
                                    " indices against " + std::to_string(previous.size()));
    constexpr std::size_t kBlock = 384; // indices (128 triangles)
    std::vector<IndexRun> runs;
    for (std::size_t b = 0; b < indices.size(); b += kBlock) {
        const std::size_t e = std::min(b + kBlock, indices.size());
        if (std::equal(indices.begin() + std::ptrdiff_t(b), indices.begin() + std::ptrdiff_t(e),
                       previous.begin() + std::ptrdiff_t(b)))
            continue;
        if (!runs.empty() && runs.back().end == b)
            runs.back().end = e;
        else
            runs.push_back({b, e});
    }
    return runs;
}

} // namespace snert::render
