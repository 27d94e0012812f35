// Scratch buffers shared by the chunks of one parallel pass (internal to snert_core).
//
// A chunk takes a buffer, uses it, and gives it back when the lease ends; a buffer is made only
// when none is free, so a pass makes about one per thread instead of one per chunk. Large
// buffers are then allocated, and their pages first touched, once per thread: a fresh page costs
// a page fault, which for plane-sized buffers made per chunk was a good part of a pass's time.
// A buffer's contents are whatever the previous user left: users must not read what they have
// not written.
#pragma once

#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace snert::detail {

template <class T> class ScratchPool {
  public:
    class Lease {
      public:
        Lease(ScratchPool& pool, std::unique_ptr<T> item) : pool_(pool), item_(std::move(item)) {}
        ~Lease() { pool_.give_back(std::move(item_)); }
        Lease(const Lease&) = delete;
        Lease& operator=(const Lease&) = delete;
        T& operator*() const { return *item_; }
        T* operator->() const { return item_.get(); }

      private:
        ScratchPool& pool_;
        std::unique_ptr<T> item_;
    };

    // Takes a free buffer, or one made by make() when none is free.
    template <class Make> Lease take(const Make& make) {
        {
            std::lock_guard lock(mutex_);
            if (!free_.empty()) {
                std::unique_ptr<T> item = std::move(free_.back());
                free_.pop_back();
                return Lease(*this, std::move(item));
            }
        }
        return Lease(*this, std::make_unique<T>(make()));
    }

  private:
    void give_back(std::unique_ptr<T> item) noexcept {
        std::lock_guard lock(mutex_);
        try {
            free_.push_back(std::move(item));
        } catch (...) { // no room to keep it: it is freed, and made again when needed
        }
    }

    std::mutex mutex_;
    std::vector<std::unique_ptr<T>> free_;
};

} // namespace snert::detail
