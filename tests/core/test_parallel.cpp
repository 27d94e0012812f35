// for_each_chunk (parallel.h): every chunk runs exactly once, whether the call is served by the
// pool of kept threads or by threads of its own (the pool busy with another thread's call, or
// the call made inside a chunk), and a chunk's exception reaches the caller.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <stdexcept>
#include <thread>
#include <vector>

#include "core/parallel.h"

using namespace snert;

namespace {

// Runs one call over `n` items in chunks of `chunk`: how many times each chunk ran, and whether
// every chunk got its own [begin, end).
std::vector<int> chunk_runs(std::size_t n, std::size_t chunk) {
    std::vector<std::atomic<int>> runs(chunk_count(n, chunk));
    std::atomic<bool> ranges_right{true};
    for_each_chunk(n, chunk, [&](std::size_t c, std::size_t b, std::size_t e) {
        runs[c].fetch_add(1);
        if (b != c * chunk || e != std::min(n, (c + 1) * chunk)) ranges_right = false;
    });
    std::vector<int> out;
    out.reserve(runs.size() + 1);
    for (const auto& r : runs) out.push_back(r.load());
    if (!ranges_right) out.push_back(-1);
    return out;
}

} // namespace

TEST(ForEachChunk, EveryChunkRunsOnceInManyCallsInARow) {
    ThreadLimit limit(0);
    for (int call = 0; call < 2000; ++call) {
        const std::size_t n = 1 + std::size_t(call % 37);
        const std::vector<int> runs = chunk_runs(n, 3);
        ASSERT_EQ(runs, std::vector<int>(chunk_count(n, 3), 1)) << "call " << call;
    }
}

TEST(ForEachChunk, CallsFromSeveralThreadsAtOnceEachRunEveryChunk) {
    std::atomic<int> wrong{0};
    constexpr int kCallers = 4;
    std::vector<std::thread> callers;
    callers.reserve(kCallers);
    for (int t = 0; t < kCallers; ++t)
        callers.emplace_back([&wrong, t] {
            ThreadLimit limit(0);
            for (int call = 0; call < 300; ++call) {
                const std::size_t n = 5 + std::size_t((call + t) % 23);
                if (chunk_runs(n, 2) != std::vector<int>(chunk_count(n, 2), 1)) ++wrong;
            }
        });
    for (std::thread& c : callers) c.join();
    EXPECT_EQ(wrong.load(), 0);
}

TEST(ForEachChunk, ACallInsideAChunkRunsItsOwnChunks) {
    ThreadLimit limit(0);
    std::atomic<long> sum{0};
    for_each_chunk(6, 1, [&](std::size_t outer, std::size_t, std::size_t) {
        ThreadLimit inner_limit(0); // a worker's own calls may use threads too
        for_each_chunk(10, 3, [&](std::size_t, std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) sum += long(100 * outer + i);
        });
    });
    // Each of the 6 outer chunks adds 100 * outer ten times and 0 + 1 + ... + 9.
    EXPECT_EQ(sum.load(), 10L * 100 * (0 + 1 + 2 + 3 + 4 + 5) + 6L * 45);
}

TEST(ForEachChunk, AChunksExceptionReachesTheCallerAndTheNextCallRuns) {
    ThreadLimit limit(0);
    for (int round = 0; round < 20; ++round) {
        EXPECT_THROW(for_each_chunk(8, 1,
                                    [&](std::size_t c, std::size_t, std::size_t) {
                                        if (c == std::size_t(round % 8))
                                            throw std::runtime_error("chunk failed");
                                    }),
                     std::runtime_error);
        EXPECT_EQ(chunk_runs(9, 2), std::vector<int>(5, 1));
    }
}
