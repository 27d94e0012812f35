// What glibc does with the large buffers a command frees: return them to the system, or keep
// them for the next ones. Only speed and resident memory depend on it, never a result.
#pragma once

#include <cstddef>

namespace snert::cli {

enum class FreedMemory {
    // Buffers of 256 KiB or more get pages of their own, which go back to the system when
    // freed: a batch command's later stages do not keep its earlier stages' memory resident.
    Returned,
    // Buffers under 32 MiB come from the heap, and up to 128 MiB at its top stays there: the
    // next buffers reuse pages already touched, where fresh pages fault one by one.
    Kept,
};

void set_freed_memory(FreedMemory policy);

// Grows the heap by `bytes` (at most 1 GiB; nothing touched), advises that span onto transparent
// huge pages and frees it, kept (the trim threshold raised by as much): the later buffers made
// there fault 2 MiB at a time, not 4 KiB. Nothing under the sanitizers.
void reserve_heap_on_huge_pages(std::size_t bytes);

// While alive, freed memory is kept; afterwards it is returned again, and what was kept goes back.
class KeepFreedMemory {
  public:
    KeepFreedMemory() { set_freed_memory(FreedMemory::Kept); }
    ~KeepFreedMemory() { set_freed_memory(FreedMemory::Returned); }
    KeepFreedMemory(const KeepFreedMemory&) = delete;
    KeepFreedMemory& operator=(const KeepFreedMemory&) = delete;
};

} // namespace snert::cli
