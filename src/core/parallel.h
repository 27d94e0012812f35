// A minimal parallel loop over an index range, for Jacobi steps, per-slab passes and metrics.
//
// The range is cut into chunks of a fixed size, independent of the thread count, and the
// chunks are handed to up to one thread per core. Per-chunk partial results combined in chunk
// order are therefore identical on every machine. A range of one chunk runs on the calling
// thread, where starting threads would cost more than the work.
//
// How many threads: one per core, unless a ThreadLimit is alive on the calling thread. The
// limit is scoped to the thread that sets it (a benchmark's `--threads 1`, an embedding program
// that runs its own pool) and changes speed only, never a result.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace snert {

namespace detail {
inline thread_local unsigned thread_limit = 0; // 0: one thread per core
} // namespace detail

// While alive, for_each_chunk calls made on this thread use at most `threads` threads (0: one
// per core). Limits nest; the previous one comes back on destruction.
class ThreadLimit {
  public:
    explicit ThreadLimit(unsigned threads) : previous_(detail::thread_limit) {
        detail::thread_limit = threads;
    }
    ~ThreadLimit() { detail::thread_limit = previous_; }
    ThreadLimit(const ThreadLimit&) = delete;
    ThreadLimit& operator=(const ThreadLimit&) = delete;

  private:
    unsigned previous_;
};

// Threads for_each_chunk may use on the calling thread: the ThreadLimit, else the core count.
inline unsigned thread_budget() {
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    return detail::thread_limit == 0 ? cores : std::min(detail::thread_limit, cores);
}

// Number of chunks for_each_chunk uses for n items.
inline std::size_t chunk_count(std::size_t n, std::size_t chunk_size) {
    return (n + chunk_size - 1) / chunk_size;
}

// Calls body(chunk, begin, end) for the chunks of [0, n) of `chunk_size` items, possibly
// concurrently. The first exception thrown by a chunk (a cancellation, say) stops the handing
// out of further chunks and is rethrown after every thread has joined.
template <class Body> void for_each_chunk(std::size_t n, std::size_t chunk_size, const Body& body) {
    const std::size_t chunks = chunk_count(n, chunk_size);
    const std::size_t threads = std::min<std::size_t>(chunks, thread_budget());
    auto run_chunk = [&](std::size_t c) {
        body(c, c * chunk_size, std::min(n, (c + 1) * chunk_size));
    };
    if (threads <= 1) {
        for (std::size_t c = 0; c < chunks; ++c) run_chunk(c);
        return;
    }
    // The calling thread only waits. Bodies read the caller's locals by reference (a span, a
    // scale), and a caller running chunks itself spilled its inlined body's temporaries onto the
    // same cache lines: each store took those lines from the other threads, and a pass of cheap
    // bodies ran 2x slower on two threads than on one.
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    auto worker = [&] {
        for (std::size_t c = next++; c < chunks; c = next++) {
            try {
                run_chunk(c);
            } catch (...) {
                std::lock_guard lock(failure_mutex);
                if (!failure) failure = std::current_exception();
                next = chunks;
            }
        }
    };
    {
        std::vector<std::jthread> pool;
        pool.reserve(threads);
        for (std::size_t t = 0; t < threads; ++t) pool.emplace_back(worker);
    } // joins
    if (failure) std::rethrow_exception(failure);
}

} // namespace snert
