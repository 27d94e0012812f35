// Progress and cancellation for long computations.
//
// Long functions take a `const Progress&`, call `progress.update(fraction)` about once per
// slice (never per voxel), and stop by throwing `Cancelled` when the caller requested it. The
// default Progress reports nothing and never cancels, so a library user can ignore it.
#pragma once

#include <exception>
#include <functional>
#include <stop_token>

namespace snert {

struct Cancelled : std::exception {
    const char* what() const noexcept override { return "cancelled"; }
};

struct Progress {
    std::stop_token stop;                       // cancellation request (default: never)
    std::function<void(float fraction)> report; // called with 0..1; must be thread-safe

    void update(float fraction) const {
        if (stop.stop_requested()) throw Cancelled();
        if (report) report(fraction);
    }
};

} // namespace snert
