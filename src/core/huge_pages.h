// Large fresh buffers on transparent huge pages (internal to snert_core and snert_io).
//
// A fresh buffer costs a page fault per 4 KiB page when first written, and for the volume- and
// mesh-sized buffers of the readers, segmentation, Marching Cubes and the net those faults were a
// good part of the run time (a 256^3 segmentation: 4096 faults, about as long as thresholding it).
// Where Linux allows transparent huge pages on request (its default "madvise" mode), the buffer
// asks for them and faults 2 MiB at a time. Elsewhere, or when refused, nothing changes: only speed
// is at stake, never contents.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace snert::detail {

// Sizes the empty vector `v` to n copies of `value`, its storage advised to use huge pages first.
template <class T>
void resize_on_huge_pages(std::vector<T>& v, std::size_t n, const T& value = T()) {
    v.reserve(n);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    // The whole 2 MiB pages within the storage (std::align: no integer-to-pointer cast).
    constexpr std::size_t kHuge = std::size_t(1) << 21;
    void* first = static_cast<void*>(v.data());
    std::size_t space = n * sizeof(T);
    if (std::align(kHuge, kHuge, first, space) != nullptr)
        madvise(first, space & ~(kHuge - 1), MADV_HUGEPAGE);
#endif
    v.resize(n, value);
}

// Makes `v` hold n copies of `value`: in its own storage when that has room (pages already
// touched, no faults), else in fresh storage on huge pages, as resize_on_huge_pages.
template <class T>
void assign_on_huge_pages(std::vector<T>& v, std::size_t n, const T& value = T()) {
    if (v.capacity() >= n) {
        v.assign(n, value);
        return;
    }
    std::vector<T>().swap(v);
    resize_on_huge_pages(v, n, value);
}

} // namespace snert::detail
