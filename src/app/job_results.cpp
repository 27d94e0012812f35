// Applying the worker's messages on the UI thread.
#include "job_results.h"

#include <type_traits>

namespace snert::app {

void JobResults::start(std::uint64_t new_generation) {
    generation = new_generation;
    net.reset();
    iterations.clear();
    finished.reset();
    compactness.reset();
    distances.reset();
    error.clear();
    mc_current = frame_current = source_current = false;
    frame_recomputed = false;
}

bool JobResults::apply(const Message& message) {
    if (message.generation != generation) return false;
    std::visit(
        [this](const auto& m) {
            using T = std::decay_t<decltype(m)>;
            if constexpr (std::is_same_v<T, VolumeMessage>) {
                source = m.source;
                iso = m.iso;
                analytic_reference = m.analytic_reference;
                source_current = true;
            } else if constexpr (std::is_same_v<T, MarchingCubesMessage>) {
                mc = m.mesh;
                mc_current = true;
            } else if constexpr (std::is_same_v<T, NetMessage>) {
                net = m;
            } else if constexpr (std::is_same_v<T, IterationMessage>) {
                const auto k = std::size_t(m.stats.iteration);
                if (iterations.size() <= k) iterations.resize(k + 1);
                iterations[k] = m.stats;
            } else if constexpr (std::is_same_v<T, FrameMessage>) {
                frame = m.mesh;
                frame_recomputed = m.recomputed;
                frame_current = true;
            } else if constexpr (std::is_same_v<T, FrameMetricsMessage>) {
                // It measures a quick frame; a frame measured already (the relaxation's last,
                // which may share the quick one's geometry) stays.
                if (frame && m.mesh && frame->geometry == m.mesh->geometry &&
                    !frame->metrics_complete)
                    frame = m.mesh;
            } else if constexpr (std::is_same_v<T, FinishedMessage>) {
                finished = m;
            } else if constexpr (std::is_same_v<T, CompactnessMessage>) {
                compactness = m;
            } else if constexpr (std::is_same_v<T, DistanceMessage>) {
                distances = m;
            } else if constexpr (std::is_same_v<T, FailedMessage>) {
                error = m.error;
            }
        },
        message.payload);
    return true;
}

int JobResults::apply(const std::vector<Message>& messages) {
    int current = 0;
    for (const Message& m : messages) current += apply(m) ? 1 : 0;
    return current;
}

} // namespace snert::app
