// A minimal parallel loop over an index range, for Jacobi steps, per-slab passes and metrics.
//
// The range is cut into chunks of a fixed size, independent of the thread count, and the
// chunks are handed to up to one thread per core. Per-chunk partial results combined in chunk
// order are therefore identical on every machine. A range of one chunk runs on the calling
// thread, where starting threads would cost more than the work.
//
// How many threads: one per core, unless a ThreadLimit is alive on the calling thread. The
// limit is scoped to the thread that sets it (a benchmark's `--threads 1`, an embedding program
// that runs its own pool) and changes speed only, never a result. The threads are kept between
// calls (detail::WorkerPool): after its first parallel call a program holds up to one idle
// thread per core until it ends.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
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

namespace detail {

// Threads kept between for_each_chunk calls: starting and joining two threads took about 100 us a
// call here, and a relaxation step makes about 21 calls (Marching Cubes on the 256^3 sphere 5 in
// 7.5 ms on two threads). The pool serves one call at a time; a call that finds it busy (another
// thread's call, or one made inside a chunk) starts threads of its own. Its workers wait for work
// until the program ends, when they are joined (their thread-local buffers freed).
class WorkerPool {
  public:
    static WorkerPool& instance() {
        static WorkerPool pool;
        return pool;
    }
    ~WorkerPool() {
        const std::lock_guard busy(busy_); // a call still being served ends first
        {
            const std::lock_guard lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        for (std::thread& w : workers_) w.join();
    }
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;
    // Runs work(context) on `threads` workers at once and returns when all have returned; false,
    // running nothing, when the pool is busy. `work` must not throw.
    bool run(std::size_t threads, void (*work)(void*), void* context) {
        std::unique_lock busy(busy_, std::try_to_lock);
        if (!busy.owns_lock()) return false;
        std::unique_lock lock(mutex_);
        while (workers_.size() < threads) {
            const std::size_t index = workers_.size();
            workers_.emplace_back([this, index, seen = generation_] { serve(index, seen); });
        }
        work_ = work, context_ = context, active_ = threads, remaining_ = threads;
        ++generation_;
        wake_.notify_all();
        done_.wait(lock, [&] { return remaining_ == 0; });
        return true;
    }

  private:
    WorkerPool() = default;
    // Worker `index`: runs each call's work when the call asks for more than `index` workers.
    void serve(std::size_t index, std::uint64_t seen) {
        std::unique_lock lock(mutex_);
        for (;;) {
            wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) return;
            seen = generation_;
            if (index >= active_) continue;
            void (*const work)(void*) = work_;
            void* const context = context_;
            lock.unlock();
            work(context);
            lock.lock();
            if (--remaining_ == 0) done_.notify_one();
        }
    }
    std::mutex busy_;  // held by the call the pool serves
    std::mutex mutex_; // guards what follows
    std::condition_variable wake_, done_;
    std::vector<std::thread> workers_;
    std::uint64_t generation_ = 0; // one more for every call served
    void (*work_)(void*) = nullptr;
    void* context_ = nullptr;
    std::size_t active_ = 0, remaining_ = 0;
    bool stop_ = false; // the program ends
};

} // namespace detail

// Calls body(chunk, begin, end) for the chunks of [0, n) of `chunk_size` items, possibly
// concurrently. The first exception thrown by a chunk (a cancellation, say) stops the handing
// out of further chunks and is rethrown once every thread has finished its chunks.
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
    const auto run_worker = [](void* w) { (*static_cast<decltype(worker)*>(w))(); };
    if (!detail::WorkerPool::instance().run(threads, run_worker, &worker)) {
        std::vector<std::jthread> own;
        own.reserve(threads);
        for (std::size_t t = 0; t < threads; ++t) own.emplace_back(worker);
    } // joins its own threads; the pool's are done when run() returns
    if (failure) std::rethrow_exception(failure);
}

} // namespace snert
