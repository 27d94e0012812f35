// The scripted session of `snert gui --stats`.
#include "stats_session.h"

#include <algorithm>
#include <cstdio>
#include <numeric>

#include "app.h"
#include "view_renderer.h"

namespace snert::app {

namespace {

constexpr int kSteps[] = {-1, -1, -1, +1, +1, +1};
constexpr double kTurnSeconds = 2.0;
constexpr int kTurnMinFrames = 10, kTurnMaxFrames = 120;
constexpr float kTurnPerFrame = 0.03f; // radians: a steady drag

double mean(const std::vector<double>& v) {
    return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

double max(const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

// The largest after the first.
double max_later(const std::vector<double>& v) {
    return v.size() < 2 ? 0.0 : *std::max_element(v.begin() + 1, v.end());
}

std::size_t count_over(const std::vector<double>& v, double limit) {
    return std::size_t(std::count_if(v.begin(), v.end(), [&](double x) { return x > limit; }));
}

// What `snert compare` makes is on screen: Marching Cubes and the relaxation's last mesh,
// measured (the convergence curves of every iteration may still be filling in).
bool comparison_shown(const App& app) {
    const JobResults& r = app.results();
    return r.mc && r.frame && r.mc_current && r.frame_current && r.mc->metrics_complete &&
           r.frame->last && r.frame->metrics_complete;
}

} // namespace

StatsSession::StatsSession() : start_(Clock::now()) {}

double StatsSession::since_start(Clock::time_point t) const {
    return std::chrono::duration<double>(t - start_).count();
}

void StatsSession::before_frame(App& app) {
    if (phase_ == Phase::Stepping && !step_waiting_) {
        const int delta = kSteps[step_index_];
        app.perform(delta < 0 ? Action::StepBack : Action::StepForward);
        step_target_ = app.shown_iteration();
        step_start_ = Clock::now();
        step_waiting_ = true;
    } else if (phase_ == Phase::Turning) {
        if (turn_frames_ == 0) turn_start_ = Clock::now();
        app.turn_camera(kTurnPerFrame, 0.0f);
    }
}

void StatsSession::after_frame(const App& app, double frame_ms) {
    const auto now = Clock::now();
    const JobResults& r = app.results();
    switch (phase_) {
    case Phase::Computing:
        computing_frames_ms_.push_back(frame_ms);
        if (load_s_ < 0 && r.source_current) load_s_ = since_start(now);
        if (mc_shown_s_ < 0 && r.mc && r.mc_current && app.view_renderer().shows_mesh(0))
            mc_shown_s_ = since_start(now);
        if (curves_s_ < 0 && r.finished) curves_s_ = since_start(now);
        if (done_s_ < 0 && comparison_shown(app)) {
            done_s_ = since_start(now);
            mc_triangles_ = r.mc->mesh.triangle_count();
            net_triangles_ = r.frame->mesh.triangle_count();
            iterations_ = r.frame->iteration;
            const ViewRenderer& views = app.view_renderer();
            mesh_draws_ = views.view_draws(0) + views.view_draws(1);
            preview_draws_ = views.preview_draws(0) + views.preview_draws(1);
            part_draws_ = views.part_draws();
            part_ms_ = views.part_ms();
            largest_part_ms_ = views.largest_part_ms();
        }
        if (done_s_ >= 0 && curves_s_ >= 0) phase_ = Phase::Stepping;
        break;
    case Phase::Stepping:
        if (step_waiting_ && r.frame && r.frame->iteration == step_target_) {
            step_latencies_s_.push_back(std::chrono::duration<double>(now - step_start_).count());
            step_waiting_ = false;
            if (++step_index_ == int(std::size(kSteps))) phase_ = Phase::Settling;
        }
        break;
    case Phase::Settling: // the last step's measurement done: turning alone is measured
        if (!app.worker().busy()) phase_ = Phase::Turning;
        break;
    case Phase::Turning:
        turning_frames_ms_.push_back(frame_ms);
        ++turn_frames_;
        turn_s_ = std::chrono::duration<double>(now - turn_start_).count();
        if (turn_frames_ >= kTurnMaxFrames ||
            (turn_frames_ >= kTurnMinFrames && turn_s_ >= kTurnSeconds))
            phase_ = Phase::Done;
        break;
    case Phase::Done:
        break;
    }
}

std::string StatsSession::json() const {
    const double turn_fps = turn_s_ > 0 ? turn_frames_ / turn_s_ : 0.0;
    char text[1024];
    std::snprintf(
        text, sizeof text,
        "{\"load_s\": %.3f, \"load_to_mc_shown_s\": %.3f, \"comparison_s\": %.3f, "
        "\"load_to_done_s\": %.3f, \"curves_s\": %.3f, \"frames\": %zu, \"frame_ms_mean\": %.2f, "
        "\"frame_ms_max\": %.2f, \"frames_over_50_ms\": %zu, \"first_frame_ms\": %.2f, "
        "\"frame_ms_max_later\": %.2f, \"step_latency_s_mean\": %.3f, "
        "\"step_latency_s_max\": %.3f, "
        "\"turn_fps\": %.2f, \"turn_frame_ms_max\": %.2f, \"mc_triangles\": %zu, "
        "\"net_triangles\": %zu, \"iterations\": %d, \"mesh_draws\": %d, \"preview_draws\": %d, "
        "\"part_draws\": %d, \"part_ms\": %.1f, \"part_ms_max\": %.1f}",
        load_s_, mc_shown_s_ - load_s_, done_s_, done_s_ - load_s_, curves_s_,
        computing_frames_ms_.size(), mean(computing_frames_ms_), max(computing_frames_ms_),
        count_over(computing_frames_ms_, 50.0),
        computing_frames_ms_.empty() ? 0.0 : computing_frames_ms_.front(),
        max_later(computing_frames_ms_), mean(step_latencies_s_), max(step_latencies_s_), turn_fps,
        max(turning_frames_ms_), mc_triangles_, net_triangles_, iterations_, mesh_draws_,
        preview_draws_, part_draws_, part_ms_, largest_part_ms_);
    return text;
}

std::string StatsSession::table() const {
    const double turn_fps = turn_s_ > 0 ? turn_frames_ / turn_s_ : 0.0;
    char text[1024];
    std::snprintf(
        text, sizeof text,
        "load                      %8.3f s\n"
        "loaded -> MC shown        %8.3f s\n"
        "whole comparison          %8.3f s  (%d iterations; %zu + %zu triangles)\n"
        "convergence curves done   %8.3f s\n"
        "UI frame while computing  %8.2f ms mean, %.2f ms max (%zu frames, %zu over 50 ms)\n"
        "step latency              %8.3f s mean, %.3f s max\n"
        "turning the camera        %8.2f fps\n",
        load_s_, mc_shown_s_ - load_s_, done_s_, iterations_, mc_triangles_, net_triangles_,
        curves_s_, mean(computing_frames_ms_), max(computing_frames_ms_),
        computing_frames_ms_.size(), count_over(computing_frames_ms_, 50.0),
        mean(step_latencies_s_), max(step_latencies_s_), turn_fps);
    return text;
}

} // namespace snert::app
