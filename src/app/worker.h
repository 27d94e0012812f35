// The app's background worker: one thread that owns the computation (load, segment, Marching
// Cubes, SurfaceNet, relaxation), so the UI thread never computes a mesh and never waits.
//
// Contract with the UI thread:
//  - request(job) starts a new job and returns its generation. The running job is cancelled
//    (its stop token is triggered; core functions poll it once per slab or iteration) and only
//    the newest request is ever started: requests that arrive while another is pending replace
//    it ("latest wins"). A hundred requests in one frame start at most one job.
//  - Progress is published as atomics (JobProgress) the UI reads every frame.
//  - Results come back as Messages in an outbox the UI drains once per frame with drain();
//    every message carries the generation of the job that made it, so the UI drops stale ones.
//    drain() only swaps a vector under a mutex: it never waits for a computation.
//  - The relaxation publishes every iteration at once: an IterationMessage (iteration and
//    largest move), and the positions go into the worker's IterationHistory under the memory
//    budget. Its convergence numbers follow once the relaxation is done (a second
//    IterationMessage, measured), so measuring never slows the relaxation down.
//  - A second thread, the measurer, does the measuring (seconds on a large mesh) while the
//    worker keeps serving frames: the iterations' numbers, then the FinishedMessage (last of a
//    job), and the full metrics of a frame the user stays on for a moment
//    (FrameMetricsMessage; frames are posted quick first: mesh, quality, normals, counts).
//  - Meshes of the relaxed net (FrameMessage) are made on request: show_iteration(k) asks for
//    iteration k (recomputed from a keyframe when it is no longer stored), show_iteration(kLive)
//    follows the newest iteration. While following, a new frame is made only once the UI has
//    drained the previous one, so a fast relaxation does not spend its time on frames nobody
//    sees, and only once live_frame_spacing times the last one's making has passed since it
//    was made, so a clinical mesh's frames do not make the relaxation half as slow again; the
//    last iteration's frame is always sent. Undrained frames are replaced, not queued.
//  - want_compactness(): once the job (or a continuation) is finished, the measurer reduces its
//    two last meshes (CompactnessMessage, after the FinishedMessage): the compactness curves and
//    the equal-count pair. Only on request (the app's Compactness tab or its switch): on a large
//    scan it takes minutes of the measurer's time.
//  - set_color_by(): while the views colour by a distance (to the iso-surface, to the other
//    mesh), each frame posted is followed by a DistanceMessage for the pair (MC and that
//    frame), measured on the worker thread; nothing is measured while a shape is chosen.
//  - continue_relaxation() relaxes the finished job further, up to `extra` iterations or until
//    the largest move falls under epsilon ("run to convergence").
//  - The worker never touches GL or ImGui. The destructor cancels and joins.
//
// The computation is the pipeline's (core/pipeline.h), as the CLI runs it: the input is opened
// with io/source.h's open_source; Marching Cubes is run_method's (on the label's mask at 0.5
// when the input has one); the net is run_surface_net's, observed (NetObserver), so every
// iteration reaches the history; "run to convergence" continues with relax() from the newest
// positions; every frame's metrics and convergence number is measure()'s.
//
// Caches: the last opened input is kept while its SourceSpec stays equal, so changing a
// parameter does not reload the file; its copy closed at the border while iso and inside stay
// the same; the last Marching Cubes result while input, iso, inside and closing stay the same.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stop_token>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "core/compactness.h"
#include "core/pipeline.h"
#include "core/triangle_distances.h"
#include "io/source.h"
#include "render/index_runs.h"
#include "iteration_history.h"
#include "preview_mesh.h"

namespace snert::app {

// One job: an input and the pipeline's parameters (DESIGN.md).
struct JobRequest {
    SourceSpec volume;
    std::optional<float> iso;  // empty: the input's suggested iso
    PipelineOptions options;   // options.iso and options.relax.iso are set from the iso
    bool close_border = false; // close the surfaces at the volume border (io/source.h)
};

enum class Stage : int { Idle, Load, Segment, MarchingCubes, Net, Relax, Done, Failed };
inline constexpr int kStageCount = 8;
const char* stage_name(Stage stage); // "loading", "segmenting", ...

// Written by the worker, read by the UI every frame (relaxed atomics: numbers for display).
struct JobProgress {
    std::atomic<std::uint64_t> generation{0}; // job these numbers belong to
    std::atomic<int> stage{int(Stage::Idle)};
    std::array<std::atomic<float>, kStageCount> fraction{}; // 0..1 per stage
    std::atomic<int> iteration{0};                          // iterations done in the relaxation
    std::atomic<int> max_iterations{0};
};

// A mesh ready to draw, with its numbers. World units; quality per triangle for colouring and
// smooth normals per vertex, both made on the worker so the UI thread only uploads them.
struct DisplayMesh {
    Method method = Method::MarchingCubes;
    int iteration = -1; // relaxation iteration; -1 for Marching Cubes
    Mesh mesh;
    TriangleMeasures shapes; // q, q60, radius ratio and the angles per triangle (core/metrics.h)
    // Mean and histogram of each shape measure (ShapeMeasure order), for the histogram panel.
    // The distances are not the mesh's alone: they come as a DistanceMessage for the pair.
    std::array<MeasureSummary, 3> summaries{};
    std::vector<glm::vec3> normals; // area-weighted, per vertex
    MethodMetrics metrics;          // counts and quality only while !metrics_complete
    bool metrics_complete = true;   // false: a quick frame; the measured one follows
    bool last = false;              // the relaxation's last iteration (the pipeline's mesh)
    // Drawn while the camera moves (large meshes only); shared by the frames of one job.
    std::shared_ptr<const PreviewMesh> preview;
    std::uint64_t geometry = 0; // equal for two DisplayMeshes with the same mesh
    // The runs of the indices that differ from the mesh of geometry `changed_since` (0: none
    // known), found on the worker: the UI thread then sends them without comparing the meshes.
    std::uint64_t changed_since = 0;
    std::vector<render::IndexRun> changed_runs;

    // A shape measure's values and summary (empty, and a zero summary, for a distance).
    std::span<const float> values(ShapeMeasure measure) const;
    const MeasureSummary& summary(ShapeMeasure measure) const;
    // Fills shapes and summaries from the mesh (the worker's job).
    void measure_triangles();
    // A copy of every member (a new member goes there too), the large arrays in fresh storage on
    // huge pages: a quick frame's measured version.
    std::shared_ptr<DisplayMesh> copy() const;
};

struct VolumeMessage {
    std::shared_ptr<const Source> source;
    float iso = 0.0f;                // the iso this job uses
    bool analytic_reference = false; // accuracy is measured against the exact surface
};
struct MarchingCubesMessage {
    std::shared_ptr<const DisplayMesh> mesh;
};
struct NetMessage {
    std::size_t nodes = 0, links = 0, quads = 0;
    int max_iterations = 0;
    double ms = 0; // building the net and the gradient field
    // The net, its gradient field and options, to redo an iteration (the slice view's node
    // inspector); shared, read-only.
    std::shared_ptr<const RelaxContext> context;
};
// Posted twice per iteration: when it is done (iteration and max_move only), and once the
// relaxation has finished, measured (stats.measured), oldest first.
struct IterationMessage {
    IterationStats stats; // iteration 0 is the initial net
};
struct FrameMessage {
    std::shared_ptr<const DisplayMesh> mesh;
    bool recomputed = false; // made from a keyframe (the iteration was not stored)
};
struct FinishedMessage {
    int iterations = 0;     // relaxation iterations done
    bool converged = false; // the largest move fell under epsilon
    double ms = 0;          // whole job
};
struct FailedMessage {
    std::string error; // one line, names the input
};
// The measured version of a quick frame (same geometry): replaces the frame shown only while
// it is still that one.
struct FrameMetricsMessage {
    std::shared_ptr<const DisplayMesh> mesh;
};

// Compactness of the job's last meshes (core/compactness.h), measured on request after the
// FinishedMessage: each mesh's compactness curve, and both reduced to the smaller
// triangle count and measured again (the "equal triangle count" switch shows these). Curves
// empty and meshes null where a mesh has no triangle.
struct CompactnessMessage {
    std::vector<CompactnessPoint> mc_curve, net_curve;
    std::size_t equal_count = 0;
    std::shared_ptr<const DisplayMesh> mc_equal, net_equal; // net_equal->iteration: the last
    DecimationReport mc_report, net_report;
};

// The distance colouring of the pair shown (core/triangle_distances.h's pair_distances: first
// Marching Cubes, second the net's frame), made only while a distance is chosen
// (set_color_by), after each frame posted, so it follows the iteration slider. The geometries
// name the two meshes it was measured on.
struct DistanceMessage {
    std::shared_ptr<const PairDistances> distances;
    std::uint64_t mc_geometry = 0, net_geometry = 0;
    int iteration = 0; // the net frame's
};

using Payload = std::variant<VolumeMessage, MarchingCubesMessage, NetMessage, IterationMessage,
                             FrameMessage, FinishedMessage, FailedMessage, FrameMetricsMessage,
                             CompactnessMessage, DistanceMessage>;
struct Message {
    std::uint64_t generation = 0;
    Payload payload;
};

// Whether a message is a result the window shows at once (a mesh, metrics, the end of a job),
// not an iteration's numbers: those come about ten a second during a relaxation on a clinical
// CT, and a frame for each would take the processor from the relaxation for a counter and a
// plot that the next of the window's progress frames shows anyway.
bool wakes_the_window(const Payload& payload);

struct WorkerOptions {
    std::size_t history_budget_bytes = std::size_t(256) << 20; // stored positions (see history)
    // The worker's threads give way to the window's (a lower priority): for a window drawn by
    // software GL beside the computation. Off for drivers that wait for the worker frame after
    // frame (tests, headless), where it would only slow the worker down.
    bool give_way_to_the_ui = false;
    // While the views follow the relaxation, a frame that took m to make is followed by the
    // next one live_frame_spacing * m later at the earliest: frames take at most about
    // 1 / (1 + spacing) of the worker's time, and the window's drawing of each (a clinical
    // mesh in parts, software GL) about as much again (worker.cpp says why).
    double live_frame_spacing = 8.0;
    // Called, on the thread that posts, once a result can be drained (wakes_the_window): a
    // window that draws only a few frames a second while the worker computes wakes at once for
    // its results. It must be safe to call from any thread.
    std::function<void()> on_message;
};

class Worker {
  public:
    static constexpr int kLive = -1; // show_iteration: follow the newest iteration

    explicit Worker(WorkerOptions options = {});
    ~Worker();
    Worker(const Worker&) = delete;
    Worker& operator=(const Worker&) = delete;

    // Starts `job` (cancelling the running one) and returns its generation (1, 2, ...).
    std::uint64_t request(JobRequest job);
    // Asks for the frame of iteration k of job `generation` (clamped to what exists; kLive:
    // the newest, and keep following). Ignored for a job that is no longer current.
    void show_iteration(std::uint64_t generation, int iteration);
    // Relaxes job `generation` further from its newest iteration (after it finished).
    void continue_relaxation(std::uint64_t generation, int extra_iterations);
    // Asks for the CompactnessMessage of job `generation` (and of its continuations): made once
    // the job is finished, or at once when it is. Repeated requests cost nothing.
    void want_compactness(std::uint64_t generation);

    // What the views colour by. While it is a distance, every frame posted is followed by its
    // DistanceMessage; choosing a distance serves the frame shown again to measure it.
    void set_color_by(ShapeMeasure measure);

    // Takes the messages posted since the last call, oldest first. Never blocks on a job.
    std::vector<Message> drain();

    const JobProgress& progress() const { return progress_; }
    // Newest generation handed out by request() (0 before the first).
    std::uint64_t latest_generation() const;
    // True when drain() would return something.
    bool has_messages() const;
    // True when drain() would return a result that wakes the window (wakes_the_window).
    bool has_results() const;
    // True while a job or a frame request is being worked on or waiting.
    bool busy() const;
    // Jobs actually started / finished (not counting skipped ones); for tests and the status bar.
    std::uint64_t jobs_started() const { return jobs_started_.load(); }
    std::uint64_t jobs_finished() const { return jobs_finished_.load(); }

  private:
    struct Job;
    struct ViewRequest {
        std::uint64_t generation = 0;
        int iteration = kLive;
        bool pending = false;
        // Bumped by every request: a request made while a frame is being served (a new colour
        // measure, say) must not be cleared as done by that frame.
        std::uint64_t serial = 0;
    };

    void run(std::stop_token thread_stop);
    void run_job(const JobRequest& request, std::uint64_t generation, std::stop_token stop);
    void relax_further(std::uint64_t generation, int extra, std::stop_token stop);
    void after_iteration(Job& job, std::span<const glm::vec3> positions, float max_move,
                         std::stop_token stop);
    void serve_view(Job& job, std::stop_token stop, bool final_frame);
    void finish(Job& job, int from, bool converged);
    void feed_measurer(Job& job);
    void queue_compactness(Job& job);
    std::shared_ptr<const DisplayMesh> make_marching_cubes(const Job& job, const Volume& volume,
                                                           const Segmentation* mask,
                                                           std::stop_token stop);
    std::shared_ptr<const DisplayMesh> make_frame(Job& job, int iteration,
                                                  std::span<const glm::vec3> positions);
    std::shared_ptr<const DisplayMesh> measured_frame(const Job& job,
                                                      const DisplayMesh& quick) const;
    // The measurer: a second thread that measures frames and iterations (seconds on a large
    // mesh), so the worker keeps serving views meanwhile. A task returns what to post.
    struct MeasureTask {
        std::stop_token stop; // the job's: a cancelled job's tasks are dropped
        std::uint64_t generation = 0;
        std::function<std::optional<Payload>()> run;
        std::chrono::steady_clock::time_point not_before{}; // frames: once the user dwells
    };
    void queue_frame_measure(MeasureTask task);     // latest wins
    void queue_iteration_measure(MeasureTask task); // in order, after frames
    void measure_loop(std::stop_token thread_stop);
    void post(std::uint64_t generation, Payload payload);
    void set_stage(std::uint64_t generation, Stage stage);
    Progress stage_progress(Stage stage, std::stop_token stop);

    WorkerOptions options_;
    JobProgress progress_;
    std::atomic<std::uint64_t> jobs_started_{0}, jobs_finished_{0};

    // Shared with the UI thread, under mutex_.
    mutable std::mutex mutex_;
    std::condition_variable_any wake_;
    std::optional<JobRequest> pending_job_;
    std::uint64_t pending_generation_ = 0;
    std::uint64_t latest_generation_ = 0;
    std::stop_source job_stop_; // of the running job (and its continuation)
    ViewRequest view_;
    std::uint64_t view_serial_ = 0;
    std::optional<std::pair<std::uint64_t, int>> continue_request_;
    std::optional<std::uint64_t> compactness_request_;
    ShapeMeasure color_by_ = ShapeMeasure::Quality;
    std::vector<Message> outbox_;
    bool frame_undrained_ = false;
    bool working_ = false;
    bool measurer_hungry_ = false; // it took an iteration: feed it the next ones

    // Owned by the worker thread only.
    std::unique_ptr<Job> job_;
    std::shared_ptr<const Source> cached_source_;
    std::shared_ptr<const DisplayMesh> cached_mc_;
    float cached_mc_iso_ = 0.0f;
    InsideIs cached_mc_inside_ = InsideIs::Above;
    bool cached_mc_closed_ = false;
    // The cached input closed at the border, for the iso and inside rule it was padded at.
    std::shared_ptr<const Source> cached_closed_;
    float cached_closed_iso_ = 0.0f;
    InsideIs cached_closed_inside_ = InsideIs::Above;

    std::uint64_t next_geometry_ = 0; // worker thread only

    // The measurer's queue, under measure_mutex_ (never taken while holding mutex_).
    mutable std::mutex measure_mutex_;
    std::condition_variable_any measure_wake_;
    std::optional<MeasureTask> frame_task_;
    std::deque<MeasureTask> iteration_tasks_;
    bool measuring_ = false;

    std::jthread thread_;   // started after everything above exists, joined first
    std::jthread measurer_; // last: destroyed (joined) before everything it uses
};

} // namespace snert::app
