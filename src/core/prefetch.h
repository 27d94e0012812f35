// A hint to fetch a cache line before it is read (internal to snert_core).
//
// GCC deletes a loop whose only effect is __builtin_prefetch (C++ lets it assume that such a loop
// does nothing), so a loop over a few indices that hints at each of their lines vanished without a
// warning. On x86-64 the hint is an instruction the compiler must keep.
#pragma once

namespace snert::detail {

inline void prefetch(const void* p) {
#if defined(__GNUC__) && defined(__x86_64__)
    __asm__ volatile("prefetcht0 %0" : : "m"(*static_cast<const char*>(p)));
#elif defined(__GNUC__)
    __builtin_prefetch(p);
#else
    (void)p;
#endif
}

} // namespace snert::detail
