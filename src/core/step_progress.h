// Progress of a computation made of equal steps run by several threads (internal to
// snert_core).
//
// Each finished step reports steps done / steps, under a lock: the callback is called by one
// thread at a time, with increasing fractions, as progress.h's callers expect of a serial loop.
// A step is a slice of a pass, so the lock is taken about once per slice, never per voxel.
#pragma once

#include <cstddef>
#include <mutex>

#include "progress.h"

namespace snert::detail {

class StepProgress {
  public:
    StepProgress(const Progress& progress, std::size_t steps)
        : progress_(progress), steps_(steps) {}

    // One step done; throws Cancelled when the caller asked to stop.
    void step() {
        std::lock_guard lock(mutex_);
        ++done_;
        progress_.update(float(done_) / float(steps_ == 0 ? 1 : steps_));
    }

  private:
    const Progress& progress_;
    const std::size_t steps_;
    std::size_t done_ = 0;
    std::mutex mutex_;
};

} // namespace snert::detail
