// Large fresh buffers on transparent huge pages (internal to snert_core and snert_io).
//
// A fresh buffer costs a page fault per 4 KiB page when first written, and for the volume- and
// mesh-sized buffers of the readers, segmentation, Marching Cubes and the net those faults were a
// good part of the run time (a 256^3 segmentation: 4096 faults, about as long as thresholding it).
// Where Linux allows transparent huge pages on request (its default "madvise" mode), the buffer
// asks for them and faults 2 MiB at a time; the small pages left at a vector's head and tail are
// mapped in one call before they are written, and scratch buffers get mappings of their own that
// start on a 2 MiB boundary (ScratchArray). Elsewhere, or when refused, nothing changes: only speed
// is at stake, never contents.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "parallel.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

// Under AddressSanitizer the scratch arrays come from operator new[], where it can see overruns.
#if defined(__SANITIZE_ADDRESS__)
#define SNERT_SCRATCH_FROM_HEAP 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SNERT_SCRATCH_FROM_HEAP 1
#endif
#endif

namespace snert::detail {

// Reserves room for n values in the empty vector `v`, the whole 2 MiB pages of it advised to be
// huge pages (std::align: no integer-to-pointer cast).
template <class T> void reserve_on_huge_pages(std::vector<T>& v, std::size_t n) {
    v.reserve(n);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr std::size_t kHuge = std::size_t(1) << 21;
    void* first = static_cast<void*>(v.data());
    std::size_t space = n * sizeof(T);
    if (std::align(kHuge, kHuge, first, space) != nullptr)
        madvise(first, space & ~(kHuge - 1), MADV_HUGEPAGE);
#endif
}

// Has the kernel map the whole 4 KiB pages of [begin, begin + bytes) at once, for memory about to
// be written. The small pages of a heap block (before and after its huge ones) otherwise fault one
// by one as they are first written, each a trip into the kernel (about 10 us on a virtual
// machine); asked for together, they are mapped in one call. The kernel zeroes each page on the
// calling thread, and on a virtual machine the host may have to back it first: a volume's 400 MiB
// took 0.4-0.8 s on one thread. A buffer of several pieces is therefore mapped piece by piece on
// every thread.
inline void map_pages_for_writing(void* begin, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    constexpr std::size_t kPage = std::size_t(1) << 12;
    constexpr std::size_t kPiece = std::size_t(1) << 24; // 16 MiB: whole huge pages
    if (std::align(kPage, kPage, begin, bytes) == nullptr) return;
    bytes &= ~(kPage - 1);
    auto* const first = static_cast<unsigned char*>(begin);
    if (bytes < 2 * kPiece) {
        madvise(first, bytes, MADV_POPULATE_WRITE);
        return;
    }
    for_each_chunk(bytes, kPiece, [&](std::size_t, std::size_t offset, std::size_t end) {
        madvise(first + offset, end - offset, MADV_POPULATE_WRITE);
    });
#else
    (void)begin;
    (void)bytes;
#endif
}

// Reserves room for n values in the empty vector `v` as reserve_on_huge_pages, the pages mapped in
// one call when there are enough of them.
template <class T> void reserve_mapped_on_huge_pages(std::vector<T>& v, std::size_t n) {
    reserve_on_huge_pages(v, n);
    constexpr std::size_t kWorthACall = std::size_t(1) << 18;
    if (n * sizeof(T) >= kWorthACall)
        map_pages_for_writing(static_cast<void*>(v.data()), n * sizeof(T));
}

// Sizes the empty vector `v` to n copies of `value`, its storage advised to use huge pages and
// mapped in one call first.
template <class T>
void resize_on_huge_pages(std::vector<T>& v, std::size_t n, const T& value = T()) {
    reserve_mapped_on_huge_pages(v, n);
    v.resize(n, value);
}

// A copy of `from` in fresh storage on huge pages, mapped in one call first.
template <class T> std::vector<T> copy_on_huge_pages(const std::vector<T>& from) {
    std::vector<T> to;
    reserve_mapped_on_huge_pages(to, from.size());
    to.assign(from.begin(), from.end());
    return to;
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

// A scratch array of n trivial values, left uninitialised, on a mapping of its own that starts on
// a 2 MiB boundary, so that every whole 2 MiB of it can be a huge page. A heap block starts
// anywhere in a page, and the part of it before its first 2 MiB boundary faults 4 KiB at a time:
// the classification's bits of a 512 x 512 x 400 CT (13 MB, made again on every run) took 3 300
// faults. The mapping ends at the last 4 KiB page in use, so the array never takes more memory
// than a heap block would.
template <class T> class ScratchArray {
    static_assert(std::is_trivial_v<T>, "a scratch array is never constructed element-wise");

  public:
    ScratchArray() = default;
    explicit ScratchArray(std::size_t n) {
        if (n == 0) return;
        if (n > (SIZE_MAX - 2 * kHuge) / sizeof(T)) throw std::bad_alloc();
        bytes_ = (n * sizeof(T) + kPage - 1) & ~(kPage - 1);
#if defined(__linux__) && defined(MADV_HUGEPAGE) && !defined(SNERT_SCRATCH_FROM_HEAP)
        if (bytes_ >= kHuge) {
            // Over-map by 2 MiB, then give back what lies before the boundary and after the end
            // (mmap's pages are 4 KiB-aligned, so the boundary is at most 2 MiB - 4 KiB in).
            void* block = mmap(nullptr, bytes_ + kHuge, PROT_READ | PROT_WRITE,
                               MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
            if (block == MAP_FAILED) throw std::bad_alloc();
            auto* first = static_cast<unsigned char*>(block);
            void* aligned = block;
            std::size_t space = bytes_ + kHuge;
            std::align(kHuge, bytes_, aligned, space);
            auto* start = static_cast<unsigned char*>(aligned);
            if (start > first) munmap(first, std::size_t(start - first));
            const std::size_t after = std::size_t(first + kHuge - start);
            if (after > 0) munmap(start + bytes_, after);
            madvise(start, bytes_, MADV_HUGEPAGE);
            data_ = static_cast<T*>(aligned);
            mapped_ = true;
            return;
        }
#endif
        data_ = new T[n];
    }
    ScratchArray(ScratchArray&& other) noexcept
        : data_(std::exchange(other.data_, nullptr)), bytes_(std::exchange(other.bytes_, 0)),
          mapped_(std::exchange(other.mapped_, false)) {}
    ScratchArray& operator=(ScratchArray&& other) noexcept {
        if (this != &other) {
            release();
            data_ = std::exchange(other.data_, nullptr);
            bytes_ = std::exchange(other.bytes_, 0);
            mapped_ = std::exchange(other.mapped_, false);
        }
        return *this;
    }
    ScratchArray(const ScratchArray&) = delete;
    ScratchArray& operator=(const ScratchArray&) = delete;
    ~ScratchArray() {
        release();
    }

    T* get() const {
        return data_;
    }
    T& operator[](std::size_t i) const {
        return data_[i];
    }

  private:
    static constexpr std::size_t kPage = std::size_t(1) << 12;
    static constexpr std::size_t kHuge = std::size_t(1) << 21;
    void release() noexcept {
#if defined(__linux__)
        if (mapped_) {
            munmap(data_, bytes_);
            data_ = nullptr;
            return;
        }
#endif
        delete[] data_;
        data_ = nullptr;
    }
    T* data_ = nullptr;
    std::size_t bytes_ = 0;
    bool mapped_ = false;
};

} // namespace snert::detail
