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
#include "freed_memory.h"

#include <malloc.h>

namespace snert::cli {

void set_freed_memory(FreedMemory policy) {
    if (policy == FreedMemory::Kept) {
        mallopt(M_MMAP_THRESHOLD, 32 << 20);
        mallopt(M_TRIM_THRESHOLD, 128 << 20);
        return;
    }
    mallopt(M_MMAP_THRESHOLD, 256 << 10);
    mallopt(M_TRIM_THRESHOLD, 128 << 10); // glibc's default
    malloc_trim(0);                       // what a Kept scope left at the heap's top
}

} // namespace snert::cli
