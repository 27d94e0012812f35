// The scratch arrays of the passes (huge_pages.h): what is written is read back, moves hand the
// storage over, and arrays of 2 MiB or more start on a 2 MiB boundary where they are mapped. The
// large buffers mapped ahead of writing (in pieces on every thread) keep their contents.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/huge_pages.h"
#include "core/parallel.h"

using snert::detail::ScratchArray;

namespace {

// Writes a pattern over all n values and checks it back.
void expect_holds(const ScratchArray<std::uint32_t>& a, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) a[i] = std::uint32_t(i * 2654435761u);
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(a[i], std::uint32_t(i * 2654435761u)) << i;
}

} // namespace

TEST(ScratchArray, SmallAndLargeArraysHoldWhatIsWritten) {
    for (std::size_t n :
         {std::size_t(1), std::size_t(1000), std::size_t(1) << 19, (std::size_t(3) << 20) + 7}) {
        const ScratchArray<std::uint32_t> a(n);
        ASSERT_NE(a.get(), nullptr) << n;
        expect_holds(a, n);
    }
    EXPECT_EQ(ScratchArray<std::uint32_t>(0).get(), nullptr);
}

TEST(ScratchArray, MovesHandTheStorageOver) {
    const std::size_t n = (std::size_t(5) << 20) / 4 + 3;
    ScratchArray<std::uint32_t> a(n);
    expect_holds(a, n);
    std::uint32_t* storage = a.get();
    ScratchArray<std::uint32_t> b(std::move(a));
    EXPECT_EQ(b.get(), storage);
    // NOLINTNEXTLINE(bugprone-use-after-move,clang-analyzer-cplusplus.Move): the moved-from state
    EXPECT_EQ(a.get(), nullptr);
    ScratchArray<std::uint32_t> c(100);
    c = std::move(b);
    EXPECT_EQ(c.get(), storage);
    EXPECT_EQ(c[n - 1], std::uint32_t((n - 1) * 2654435761u));
}

TEST(ScratchArray, LargeArraysStartOnAHugePageBoundary) {
#if defined(__linux__) && !defined(SNERT_SCRATCH_FROM_HEAP)
    const ScratchArray<std::uint8_t> large(std::size_t(2) << 20);
    // std::align leaves a pointer that is already on the boundary where it is.
    void* start = large.get();
    std::size_t space = std::size_t(2) << 20;
    EXPECT_EQ(std::align(std::size_t(1) << 21, 1, start, space), large.get());
#else
    GTEST_SKIP() << "arrays come from the heap here (not Linux, or AddressSanitizer)";
#endif
}

TEST(HugePages, LargeBuffersMappedInPiecesKeepTheirContents) {
    // Over 32 MiB, so mapped in pieces of 16 MiB; an odd size, so the last piece is short.
    const std::size_t n = (std::size_t(41) << 20) / 4 + 13;
    for (const unsigned threads : {1u, 2u}) {
        const snert::ThreadLimit limit(threads);
        std::vector<std::uint32_t> v;
        snert::detail::resize_on_huge_pages(v, n, 7u);
        ASSERT_EQ(v.size(), n);
        for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(v[i], 7u) << threads << " threads, " << i;
        // Mapping memory that already holds values, from a start inside a page, changes none.
        for (std::size_t i = 0; i < n; ++i) v[i] = std::uint32_t(i * 2654435761u);
        snert::detail::map_pages_for_writing(static_cast<void*>(v.data() + 5), (n - 9) * 4);
        for (std::size_t i = 0; i < n; ++i)
            ASSERT_EQ(v[i], std::uint32_t(i * 2654435761u)) << threads << " threads, " << i;
    }
}
