// glibc's thresholds for the two policies of freed_memory.h.
//
// Why each command takes the one it does:
// - Batch commands return: glibc's default raises its mmap threshold after each large free (up to
//   32 MiB), so the large buffers of later stages came from the heap and stayed resident after
//   use: on the 512 x 512 x 400 CT, `compare` peaked 60 MiB higher that way (bench/README.md).
// - The app keeps, so software GL's pictures, frame buffers and mesh buffers are made in memory
//   used before. Fresh pages are slow while the worker fills its own: the second view's first
//   picture took 650-800 ms in the first frames while a clinical CT was read, and the warm-up's
//   freed picture now serves both views. The app's peak memory on that CT moved by 1 %.
// - The app's heap is also grown at the start onto transparent huge pages (nothing touched):
//   the UI thread's fresh memory is software GL's, which clears a new buffer whole as it makes
//   it, and on small pages that cost 2.5 ms a MB (a clinical mesh's positions, 21 MB, in
//   55 ms; on huge pages 6-40 ms).
#include "freed_memory.h"

#include <malloc.h>
#include <sys/mman.h>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <vector>

namespace snert::cli {

namespace {
constexpr std::size_t kKeptTop = std::size_t(128) << 20; // Kept: freed memory at the heap's top
} // namespace

void set_freed_memory(FreedMemory policy) {
    if (policy == FreedMemory::Kept) {
        mallopt(M_MMAP_THRESHOLD, 32 << 20);
        mallopt(M_TRIM_THRESHOLD, int(kKeptTop));
        return;
    }
    mallopt(M_MMAP_THRESHOLD, 256 << 10);
    mallopt(M_TRIM_THRESHOLD, 128 << 10); // glibc's default
    malloc_trim(0);                       // what a Kept scope left at the heap's top
}

void reserve_heap_on_huge_pages(std::size_t bytes) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    (void)bytes; // the sanitizers' allocators have no heap top to keep
#else
    // Blocks under the mmap threshold come from the heap's top, one after another; kept there
    // once freed, as long as the top stays under the trim threshold.
    constexpr std::size_t kBlock = std::size_t(24) << 20;
    constexpr std::size_t kMost = std::size_t(1) << 30;
    bytes = std::min(bytes, kMost);
    mallopt(M_TRIM_THRESHOLD, int(bytes + kKeptTop));
    std::vector<void*> blocks;
    for (std::size_t got = 0; got < bytes; got += kBlock)
        if (void* block = std::malloc(kBlock)) blocks.push_back(block);
    // Each block's whole 2 MiB pages (a block's first and last may share theirs with its
    // neighbours' headers).
    constexpr std::size_t kHuge = std::size_t(2) << 20;
    for (void* block : blocks) {
        void* start = block;
        std::size_t space = kBlock;
        if (std::align(kHuge, kHuge, start, space))
            madvise(start, space / kHuge * kHuge, MADV_HUGEPAGE);
    }
    for (void* block : blocks) std::free(block);
#endif
}

} // namespace snert::cli
