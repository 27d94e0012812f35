// The relaxation's history under a memory budget: keyframes, and recomputation from them.
//
// Recomputation is relax() started from keyframe j (RelaxStart), so iteration k recomputed from
// it equals the relaxation's own iteration k bit for bit.
#include "iteration_history.h"

#include <stdexcept>
#include <string>

#include "core/huge_pages.h"
#include "core/progress.h"

namespace snert::app {

IterationHistory::IterationHistory(std::shared_ptr<const RelaxContext> context,
                                   std::size_t budget_bytes)
    : context_(std::move(context)), budget_bytes_(budget_bytes), latest_(context_->net->positions) {
}

std::size_t IterationHistory::frame_bytes() const {
    return context_->net->positions.size() * sizeof(glm::vec3);
}

std::span<const glm::vec3> IterationHistory::latest() const {
    return latest_;
}

void IterationHistory::append(std::span<const glm::vec3> positions) {
    if (positions.size() != context_->net->positions.size())
        throw std::invalid_argument("iteration history: " + std::to_string(positions.size()) +
                                    " positions for a net of " +
                                    std::to_string(context_->net->positions.size()) + " nodes");
    ++latest_iteration_;
    latest_.assign(positions.begin(), positions.end());
    if (latest_iteration_ % stride_ == 0) {
        frames_.emplace(latest_iteration_, detail::copy_on_huge_pages(latest_));
        stored_bytes_ += frame_bytes();
        thin_out();
    }
}

void IterationHistory::thin_out() {
    // Doubling the stride halves the kept frames; repeat until they fit (or none are left, when
    // one frame alone is over the budget).
    while (stored_bytes_ > budget_bytes_ && !frames_.empty()) {
        stride_ *= 2;
        for (auto it = frames_.begin(); it != frames_.end();) {
            if (it->first % stride_ != 0) {
                stored_bytes_ -= frame_bytes();
                it = frames_.erase(it);
            } else {
                ++it;
            }
        }
    }
}

bool IterationHistory::stored(int k) const {
    return k == 0 || k == latest_iteration_ || frames_.count(k) != 0;
}

std::vector<glm::vec3> IterationHistory::positions(int k, const std::stop_token& stop) const {
    if (k < 0 || k > latest_iteration_)
        throw std::out_of_range("iteration " + std::to_string(k) + " not in [0, " +
                                std::to_string(latest_iteration_) + "]");
    last_recomputed_steps_ = 0;
    // Copies on huge pages: 5 MB for a clinical net, which faulted 4 KiB at a time took up to
    // 28 ms of the worker for each frame it made.
    using detail::copy_on_huge_pages;
    if (k == 0) return copy_on_huge_pages(context_->net->positions);
    if (k == latest_iteration_) return copy_on_huge_pages(latest_);
    if (const auto it = frames_.find(k); it != frames_.end()) return copy_on_huge_pages(it->second);

    // The nearest start at or below k: a keyframe, the scratch frame, or the initial net.
    int start = 0;
    const std::vector<glm::vec3>* from = &context_->net->positions;
    if (auto it = frames_.upper_bound(k); it != frames_.begin()) {
        --it;
        start = it->first;
        from = &it->second;
    }
    if (scratch_iteration_ == k) return copy_on_huge_pages(scratch_);
    if (scratch_iteration_ > start && scratch_iteration_ < k) {
        start = scratch_iteration_;
        from = &scratch_;
    }

    // Iterations start + 1 .. k, whatever their moves (epsilon 0: the relaxation that made them
    // did not stop before k either).
    const RelaxContext& c = *context_;
    RelaxOptions options = c.options;
    options.max_iterations = k;
    options.epsilon = 0.0f;
    Progress progress;
    progress.stop = stop;
    RelaxResult redone = relax(*c.net, c.grey.get(), options, {}, progress, {*from, start});
    last_recomputed_steps_ = int(redone.max_moves.size());
    scratch_iteration_ = k;
    scratch_ = redone.positions;
    return std::move(redone.positions);
}

} // namespace snert::app
