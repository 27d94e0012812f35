// The relaxation's history: the node positions after every iteration, kept under a memory
// budget, so the app can step and scrub through the iterations of a large net.
//
// Iteration 0 is the initial net (the cell centres); iteration k is the result of k Jacobi
// iterations (relaxation.h). Every iteration is recorded with append(). While the stored
// positions fit in the budget every iteration is kept; beyond it the history keeps only
// keyframes, every `stride` iterations, doubling the stride (and dropping the frames that are no
// longer on it) each time the budget is exceeded again. Any iteration can still be had:
// positions(k) recomputes it from the nearest keyframe at or below k with relax(), which is
// deterministic, so the recomputed positions equal the ones the relaxation produced bit for bit.
// The latest iteration is always kept as well (the app shows it while the relaxation runs), and
// the initial positions come from the net itself, so they cost nothing.
//
// Memory: at most budget_bytes of stored frames plus the latest frame and one scratch frame
// (the last recomputed iteration, so that stepping forward one iteration costs one step).
//
// Not thread-safe: the worker thread owns its history and is the only one to use it.
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <span>
#include <stop_token>
#include <vector>

#include <glm/glm.hpp>

#include "core/metrics.h"
#include "core/relaxation.h"
#include "core/surface_net.h"
#include "core/volume.h"

namespace snert::app {

// Everything relax() needs to redo or continue iterations: the net and the gradient field as
// the pipeline made them (core/pipeline.h, NetObserver). `grey->volume` points into `volume`,
// which the context keeps alive.
struct RelaxContext {
    std::shared_ptr<const Volume> volume;
    std::shared_ptr<const SurfaceNet> net;
    std::shared_ptr<const GreyField> grey;
    RelaxOptions options;
};

// The numbers the convergence plots show, for one iteration (iteration 0: the initial net).
struct IterationStats {
    int iteration = 0;
    float max_move = 0;      // largest node move of this iteration (voxels); 0 for 0
    double quality_mean = 0; // smallest / largest angle (best 1)
    double quality_min = 0;
    double smoothness = 0;         // mean |2 pi - angle sum| (radians, best 0)
    double accuracy_vertices = -1; // mean vertex distance to the reference (voxels); -1: none
    double accuracy_faces = -1;    // mean face-centre distance (voxels); -1: none
    bool measured = false;         // false: only iteration and max_move are known yet
};

class IterationHistory {
  public:
    // `context` must outlive nothing else: the history shares it. budget_bytes bounds the
    // stored frames (0: keep only the latest; everything else is recomputed from the start).
    IterationHistory(std::shared_ptr<const RelaxContext> context, std::size_t budget_bytes);

    // Records the positions after iteration count() (the first call records iteration 1).
    // Throws std::invalid_argument when the size differs from the net's node count.
    void append(std::span<const glm::vec3> positions);

    // Iterations available, counting iteration 0 (so 1 before the first append).
    int count() const { return latest_iteration_ + 1; }
    int latest_iteration() const { return latest_iteration_; }

    // Positions after iteration k (0 <= k < count()): the stored frame, or recomputed from the
    // nearest keyframe. Throws std::out_of_range for k outside that range. The stop token is
    // polled between recomputed iterations (throws Cancelled).
    std::vector<glm::vec3> positions(int k, const std::stop_token& stop = {}) const;

    // True when iteration k is returned without recomputation.
    bool stored(int k) const;
    // Current distance between kept frames (1 while everything fits).
    int stride() const { return stride_; }
    // Bytes held by the stored frames (not counting the latest and the scratch frame).
    std::size_t stored_bytes() const { return stored_bytes_; }
    std::size_t budget_bytes() const { return budget_bytes_; }
    // Relaxation steps the last positions() call ran (0 when it was stored); for tests.
    int last_recomputed_steps() const { return last_recomputed_steps_; }

    const RelaxContext& context() const { return *context_; }
    std::span<const glm::vec3> latest() const;

  private:
    std::size_t frame_bytes() const;
    void thin_out();

    std::shared_ptr<const RelaxContext> context_;
    std::size_t budget_bytes_ = 0;
    int stride_ = 1;
    int latest_iteration_ = 0;
    std::vector<glm::vec3> latest_;                // positions after latest_iteration_
    std::map<int, std::vector<glm::vec3>> frames_; // kept iterations (multiples of stride_)
    std::size_t stored_bytes_ = 0;
    mutable int scratch_iteration_ = -1; // last recomputed iteration, or -1
    mutable std::vector<glm::vec3> scratch_;
    mutable int last_recomputed_steps_ = 0;
};

} // namespace snert::app
