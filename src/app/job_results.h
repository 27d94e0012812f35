// What the UI knows about the current job: the worker's messages applied in order, stale ones
// (from a job that a newer request replaced) dropped. GL-free; lives on the UI thread.
//
// On a new request the job-specific state (iterations, net, finished, error) is cleared, while
// the meshes and the volume of the previous job stay until the new ones arrive, so the views
// never flash empty while the worker recomputes.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "worker.h"

namespace snert::app {

struct JobResults {
    std::uint64_t generation = 0;         // the job these results follow
    std::shared_ptr<const Source> source; // the input (volume, mask, histogram, ...)
    float iso = 0.0f;                     // the iso the job uses
    bool analytic_reference = false;
    std::shared_ptr<const DisplayMesh> mc; // Marching Cubes
    std::optional<NetMessage> net;
    std::vector<IterationStats> iterations;   // [k] = iteration k, 0 = the initial net
    std::shared_ptr<const DisplayMesh> frame; // the relaxed net at frame->iteration
    bool frame_recomputed = false;
    std::optional<FinishedMessage> finished;
    std::optional<CompactnessMessage> compactness; // after `finished`
    std::optional<DistanceMessage> distances;      // the newest, while a distance is chosen
    std::string error;                             // the job failed (one line)
    bool mc_current = false;                       // mc / frame / source belong to `generation`
    bool frame_current = false;
    bool source_current = false;

    // Follow job `generation` from now on (call right after Worker::request).
    void start(std::uint64_t new_generation);
    // Applies one message; returns false (and changes nothing) when it is stale.
    bool apply(const Message& message);
    // Applies all of them; returns how many were current.
    int apply(const std::vector<Message>& messages);

    // Iterations known so far (the slider's range is [0, iteration_count() - 1]).
    int iteration_count() const { return int(iterations.size()); }
};

} // namespace snert::app
