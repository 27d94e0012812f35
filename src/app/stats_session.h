// `snert gui --stats`: a scripted session in the real window that measures whether the UI keeps
// up. It waits for the comparison (the load, Marching Cubes shown, the relaxation to its last
// iteration), steps back and forth through the iterations, turns the camera, then reports:
//   load_s               start to the input loaded (the worker's VolumeMessage)
//   load_to_mc_shown_s   loaded to the first frame that shows Marching Cubes
//   comparison_s         start to the relaxation's last mesh shown, measured (what
//                        `snert compare` makes)
//   curves_s             start to every iteration measured (the convergence curves)
//   frame_ms_mean/max    UI thread's work per frame (poll to swap) while computing
//   frames_over_50_ms    how many of those frames took longer than 50 ms
//   first_frame_ms       the first of them (it compiles the shaders and the font atlas)
//   frame_ms_max_later   the largest of the others
//   step_latency_s_*     a step pressed to the frame that shows its iteration
//   turn_fps             frames per second while the camera turns on every frame (once the
//                        worker is idle)
//   mesh_draws, preview_draws, part_draws, part_ms, part_ms_max
//                        until the comparison is shown: the views' whole meshes drawn, their
//                        stand-ins, and the parts of large meshes with their milliseconds and
//                        the largest (drawn in a frame, or between frames, where the UI thread
//                        looks at the person's input after each)
// The glue (window.cpp) calls before_frame / after_frame around each frame. GL-free.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace snert::app {

class App;

class StatsSession {
  public:
    using Clock = std::chrono::steady_clock;

    StatsSession();

    // Acts on the app before its frame: a step, a turn of the camera.
    void before_frame(App& app);
    // After the frame was drawn and presented; `frame_ms` is the UI thread's time for it.
    void after_frame(const App& app, double frame_ms);
    bool done() const { return phase_ == Phase::Done; }
    // Turning the camera stands for a drag, whose events wake every frame: no frame cap then.
    bool turning() const { return phase_ == Phase::Turning; }
    // Past the computation: the session steps and turns by itself, from frame to frame.
    bool acting() const { return phase_ != Phase::Computing; }
    // The figures as one JSON object (one line) and as a small table.
    std::string json() const;
    std::string table() const;

  private:
    enum class Phase { Computing, Stepping, Settling, Turning, Done };
    double since_start(Clock::time_point t) const;

    Phase phase_ = Phase::Computing;
    Clock::time_point start_;
    double load_s_ = -1, mc_shown_s_ = -1, done_s_ = -1, curves_s_ = -1;
    std::vector<double> computing_frames_ms_, turning_frames_ms_;
    std::size_t mc_triangles_ = 0, net_triangles_ = 0;
    // What the views drew until the comparison was shown: whole meshes (in one go or completed
    // from parts), previews, and the parts with the time they took.
    int mesh_draws_ = 0, preview_draws_ = 0, part_draws_ = 0;
    double part_ms_ = 0, largest_part_ms_ = 0;
    int iterations_ = 0;
    // Stepping: back three times, forward three times.
    int step_index_ = 0;
    bool step_waiting_ = false;
    int step_target_ = 0;
    Clock::time_point step_start_;
    std::vector<double> step_latencies_s_;
    // Turning.
    int turn_frames_ = 0;
    Clock::time_point turn_start_;
    double turn_s_ = 0;
};

} // namespace snert::app
