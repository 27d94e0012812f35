// The background worker: one thread, one job at a time, latest request wins.
//
// Locking: mutex_ guards only the hand-over fields (pending job, view request, outbox); it is
// never held while computing, so the UI thread's calls return at once. Everything the job
// computes lives in job_ and the caches, which only the worker thread touches.
#include "worker.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <limits>

#include "core/huge_pages.h"
#include "core/triangulation.h"
#include "render/normals.h"

#if defined(__linux__)
#include <sys/resource.h>
#include <unistd.h>
#endif

namespace snert::app {

namespace {

using Clock = std::chrono::steady_clock;

// How long a frame asked for must stay the newest request before the measurer measures it.
constexpr auto kDwell = std::chrono::milliseconds(250);

// The UI thread draws with the processor too (software GL on a machine without a GPU): the
// worker's threads, and the threads their parallel passes start (which inherit it), give way to
// it, so frames stay short while the worker computes; alone, they still get every core.
void lower_this_threads_priority() {
#if defined(__linux__)
    constexpr int kBackgroundNice = 10;
    setpriority(PRIO_PROCESS, id_t(gettid()), kBackgroundNice); // best effort: speed only
#endif
}

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void throw_if_stopped(const std::stop_token& stop) {
    if (stop.stop_requested()) throw Cancelled();
}

// A pipeline result ready to draw (`iteration`: of the relaxation, -1 for Marching Cubes).
std::shared_ptr<const DisplayMesh> display_mesh(MethodResult result, std::uint64_t geometry,
                                                int iteration = -1) {
    auto display = std::make_shared<DisplayMesh>();
    display->method = result.method;
    display->iteration = iteration;
    display->mesh = std::move(result.mesh);
    display->measure_triangles();
    display->normals = render::vertex_normals(display->mesh);
    display->metrics = result.metrics;
    display->geometry = geometry;
    if (iteration < 0) // the net's frames share their job's preview
        display->preview = std::make_shared<const PreviewMesh>(make_preview(display->mesh));
    return display;
}

// The views most likely hold the frame sent before this one (they take each before the next
// goes): what differs from it, found here rather than on the UI thread (10 ms there for a skin
// surface of 3.5 M triangles).
void note_index_changes(DisplayMesh& frame, const DisplayMesh* sent) {
    if (!sent || sent->mesh.indices.size() != frame.mesh.indices.size()) return;
    frame.changed_since = sent->geometry;
    frame.changed_runs = render::changed_index_runs(frame.mesh.indices, sent->mesh.indices);
}

// What a quick frame shows before it is measured: counts and the quality of its triangles.
MethodMetrics quick_metrics(const Mesh& mesh, std::span<const float> quality) {
    MethodMetrics m;
    m.vertices = mesh.vertex_count();
    m.triangles = mesh.triangle_count();
    if (quality.empty()) return m;
    double sum = 0;
    m.quality.min = 1.0;
    for (const float q : quality) {
        sum += q;
        m.quality.min = std::min(m.quality.min, double(q));
        const int bin = std::clamp(int(q * kQualityBins), 0, kQualityBins - 1);
        ++m.quality.histogram[std::size_t(bin)];
    }
    m.quality.mean = sum / double(quality.size());
    return m;
}

// The convergence numbers of one iteration: measure()'s, restricted to what the plots show.
IterationStats measure_iteration(const RelaxContext& c, const DistanceFunction& reference,
                                 MeasureOptions what, int iteration, float max_move,
                                 std::span<const glm::vec3> positions) {
    Mesh mesh = triangulate(*c.net, positions, c.options.triangulation, c.volume->spacing);
    what.convergence_only = true;
    const MethodMetrics m = measure_into_world(mesh, *c.volume, reference, what);
    IterationStats stats;
    stats.iteration = iteration;
    stats.max_move = max_move;
    stats.quality_mean = m.quality.mean;
    stats.quality_min = m.quality.min;
    stats.smoothness = m.smoothness;
    if (m.accuracy) {
        stats.accuracy_vertices = m.accuracy->vertices_mean;
        stats.accuracy_faces = m.accuracy->faces_mean;
    }
    stats.measured = true;
    return stats;
}

// The compactness of a finished job: the curves of Marching Cubes' mesh and the net's last one,
// and both reduced to the smaller count, measured as the pipeline measures (compactness.h).
CompactnessMessage measure_compactness(const RelaxContext& c, const DistanceFunction& reference,
                                       const MeasureOptions& what, const DisplayMesh& mc,
                                       Method net_method, int iteration,
                                       std::span<const glm::vec3> positions,
                                       std::uint64_t first_geometry) {
    Mesh mesh = triangulate(*c.net, positions, c.options.triangulation, c.volume->spacing);
    std::vector<MethodResult> results(2);
    results[0] = {Method::MarchingCubes, mc.mesh, mc.metrics};
    results[1].method = net_method;
    results[1].metrics = measure_into_world(mesh, *c.volume, reference, what);
    results[1].mesh = std::move(mesh);
    CompactnessMessage m;
    m.mc_curve = compactness_curve(results[0].mesh, *c.volume);
    m.net_curve = compactness_curve(results[1].mesh, *c.volume);
    m.equal_count = equal_count_target(results, std::nullopt);
    if (m.equal_count == 0) return m; // a mesh without triangles: nothing to compare
    const std::vector<DecimationReport> reports =
        reduce_to_equal_count(results, m.equal_count, *c.volume, reference, what);
    m.mc_report = reports[0];
    m.net_report = reports[1];
    m.equal_count = std::max(reports[0].achieved, reports[1].achieved); // where one stopped short
    m.mc_equal = display_mesh(std::move(results[0]), first_geometry);
    auto net = std::const_pointer_cast<DisplayMesh>(
        display_mesh(std::move(results[1]), first_geometry + 1, iteration));
    net->last = true;
    m.net_equal = net;
    return m;
}

} // namespace

const char* stage_name(Stage stage) {
    switch (stage) {
    case Stage::Idle:
        return "idle";
    case Stage::Load:
        return "loading";
    case Stage::Segment:
        return "segmenting";
    case Stage::MarchingCubes:
        return "marching cubes";
    case Stage::Net:
        return "surface net";
    case Stage::Relax:
        return "relaxing";
    case Stage::Done:
        return "done";
    case Stage::Failed:
        return "failed";
    }
    return "?";
}

struct Worker::Job {
    std::uint64_t generation = 0;
    Clock::time_point start = Clock::now();
    std::shared_ptr<const Source> source;
    PipelineOptions options;
    DistanceFunction reference;                  // voxel units; may be empty
    std::shared_ptr<const RelaxContext> context; // once the net exists
    std::unique_ptr<IterationHistory> history;
    std::shared_ptr<const DisplayMesh> final_frame; // the pipeline's own mesh of its last iteration
    int frame_sent = -1;                            // iteration of the last frame posted
    std::shared_ptr<const DisplayMesh> sent_frame;  // ... and that frame
    std::vector<float> max_moves;                   // [k]: of iteration k
    std::stop_token stop;                           // the job's
    std::shared_ptr<const PreviewMesh> preview;     // of the net's frames
    int next_to_measure = 0;                        // the next iteration for the measurer
    std::optional<FinishedMessage> finished;        // posted after the last one is measured
    bool done = false;                              // finish() was called (no relaxation runs)
    bool compactness_wanted = false, compactness_queued = false;
    Clock::time_point next_live_frame; // the earliest for a passing frame
};

Worker::Worker(WorkerOptions options)
    : options_(options), thread_([this](std::stop_token stop) { run(stop); }),
      measurer_([this](std::stop_token stop) { measure_loop(stop); }) {}

Worker::~Worker() {
    {
        std::lock_guard lock(mutex_);
        pending_job_.reset();
        job_stop_.request_stop();
    }
    thread_.request_stop();
    if (thread_.joinable()) thread_.join();
}

std::uint64_t Worker::request(JobRequest job) {
    std::lock_guard lock(mutex_);
    pending_job_ = std::move(job);
    pending_generation_ = ++latest_generation_;
    view_ = {pending_generation_, kLive, false,
             ++view_serial_}; // a new job is followed live until told otherwise
    job_stop_.request_stop(); // the running job throws Cancelled at its next poll
    wake_.notify_one();
    return pending_generation_;
}

void Worker::show_iteration(std::uint64_t generation, int iteration) {
    std::lock_guard lock(mutex_);
    if (generation != latest_generation_) return;
    view_ = {generation, iteration < 0 ? kLive : iteration, true, ++view_serial_};
    wake_.notify_one();
}

void Worker::set_color_by(ShapeMeasure measure) {
    std::lock_guard lock(mutex_);
    if (measure == color_by_) return;
    color_by_ = measure;
    // A distance is measured with the frame: serve the one shown again.
    if (is_distance(measure) && view_.generation == latest_generation_ && view_.generation != 0) {
        view_.pending = true;
        view_.serial = ++view_serial_;
        wake_.notify_one();
    }
}

void Worker::want_compactness(std::uint64_t generation) {
    std::lock_guard lock(mutex_);
    if (generation != latest_generation_) return;
    compactness_request_ = generation;
    wake_.notify_one();
}

void Worker::continue_relaxation(std::uint64_t generation, int extra_iterations) {
    std::lock_guard lock(mutex_);
    if (generation != latest_generation_ || extra_iterations <= 0) return;
    continue_request_ = {generation, extra_iterations};
    wake_.notify_one();
}

std::vector<Message> Worker::drain() {
    std::vector<Message> messages;
    std::lock_guard lock(mutex_);
    messages.swap(outbox_);
    frame_undrained_ = false;
    return messages;
}

std::uint64_t Worker::latest_generation() const {
    std::lock_guard lock(mutex_);
    return latest_generation_;
}

bool Worker::has_messages() const {
    std::lock_guard lock(mutex_);
    return !outbox_.empty();
}

bool Worker::has_results() const {
    std::lock_guard lock(mutex_);
    return std::any_of(outbox_.begin(), outbox_.end(),
                       [](const Message& m) { return wakes_the_window(m.payload); });
}

bool Worker::busy() const {
    {
        std::lock_guard lock(mutex_);
        if (working_ || pending_job_.has_value() || continue_request_.has_value() ||
            compactness_request_.has_value() || view_.pending || measurer_hungry_)
            return true;
    }
    std::lock_guard lock(measure_mutex_);
    return measuring_ || frame_task_.has_value() || !iteration_tasks_.empty();
}

void Worker::queue_frame_measure(MeasureTask task) {
    std::lock_guard lock(measure_mutex_);
    frame_task_ = std::move(task);
    measure_wake_.notify_one();
}

void Worker::queue_iteration_measure(MeasureTask task) {
    std::lock_guard lock(measure_mutex_);
    iteration_tasks_.push_back(std::move(task));
    measure_wake_.notify_one();
}

void Worker::measure_loop(std::stop_token thread_stop) {
    if (options_.give_way_to_the_ui) lower_this_threads_priority();
    std::unique_lock lock(measure_mutex_);
    while (!thread_stop.stop_requested()) {
        const auto frame_due = [this] {
            return frame_task_ && Clock::now() >= frame_task_->not_before;
        };
        if (frame_task_ && iteration_tasks_.empty() && !frame_due()) {
            const Clock::time_point due = frame_task_->not_before;
            measure_wake_.wait_until(lock, thread_stop, due,
                                     [&] { return frame_due() || !iteration_tasks_.empty(); });
        } else {
            measure_wake_.wait(lock, thread_stop, [this] {
                return frame_task_.has_value() || !iteration_tasks_.empty();
            });
        }
        if (thread_stop.stop_requested()) break;
        MeasureTask task;
        if (frame_due()) {
            task = std::move(*frame_task_);
            frame_task_.reset();
        } else if (iteration_tasks_.empty()) {
            continue; // a frame that is not due yet (it was replaced, or the wait timed out)
        } else {
            task = std::move(iteration_tasks_.front());
            iteration_tasks_.pop_front();
            std::lock_guard worker_lock(mutex_); // order: measure_mutex_, then mutex_
            measurer_hungry_ = true;
            wake_.notify_one();
        }
        if (task.stop.stop_requested()) continue; // a newer job took over
        measuring_ = true;
        lock.unlock();
        std::optional<Payload> result;
        try {
            result = task.run();
        } catch (const Cancelled&) {
        } catch (const std::exception& e) {
            result = FailedMessage{e.what()};
        }
        lock.lock();
        // Posted under measure_mutex_: once the message can be drained, busy() sees the end.
        if (result && !task.stop.stop_requested()) post(task.generation, std::move(*result));
        measuring_ = false;
    }
}

bool wakes_the_window(const Payload& payload) {
    return !std::holds_alternative<IterationMessage>(payload);
}

void Worker::post(std::uint64_t generation, Payload payload) {
    const bool wake = wakes_the_window(payload);
    {
        std::lock_guard lock(mutex_);
        bool replaced = false;
        if (std::holds_alternative<FrameMessage>(payload)) {
            frame_undrained_ = true;
            // A newer frame replaces one the UI has not taken yet: frames are views, not events.
            for (Message& m : outbox_) {
                if (m.generation == generation && std::holds_alternative<FrameMessage>(m.payload)) {
                    m.payload = std::move(payload);
                    replaced = true;
                    break;
                }
            }
        }
        if (!replaced) outbox_.push_back({generation, std::move(payload)});
    }
    if (wake && options_.on_message) options_.on_message();
}

void Worker::set_stage(std::uint64_t generation, Stage stage) {
    if (progress_.generation.load() != generation) return;
    progress_.stage.store(int(stage));
}

Progress Worker::stage_progress(Stage stage, std::stop_token stop) {
    Progress progress;
    progress.stop = std::move(stop);
    progress.report = [this, stage](float fraction) {
        progress_.fraction[std::size_t(stage)].store(fraction, std::memory_order_relaxed);
    };
    return progress;
}

void Worker::run(std::stop_token thread_stop) {
    if (options_.give_way_to_the_ui) lower_this_threads_priority();
    std::unique_lock lock(mutex_);
    while (!thread_stop.stop_requested()) {
        wake_.wait(lock, thread_stop, [this] {
            return pending_job_.has_value() || continue_request_.has_value() || view_.pending ||
                   measurer_hungry_ || compactness_request_.has_value();
        });
        if (thread_stop.stop_requested()) break;
        working_ = true;
        if (pending_job_) {
            const JobRequest request = std::move(*pending_job_);
            pending_job_.reset();
            const std::uint64_t generation = pending_generation_;
            job_stop_ = std::stop_source();
            const std::stop_token stop = job_stop_.get_token();
            if (continue_request_ && continue_request_->first != generation)
                continue_request_.reset();
            lock.unlock();
            run_job(request, generation, stop);
            lock.lock();
        } else if (continue_request_) {
            const auto [generation, extra] = *continue_request_;
            continue_request_.reset();
            const std::stop_token stop = job_stop_.get_token();
            lock.unlock();
            relax_further(generation, extra, stop);
            lock.lock();
        } else if (compactness_request_) {
            const std::uint64_t generation = *compactness_request_;
            compactness_request_.reset();
            lock.unlock();
            if (job_ && job_->history && job_->generation == generation) {
                job_->compactness_wanted = true;
                // Once the FinishedMessage is on its way: the compactness comes after it.
                try {
                    if (job_->done && !job_->finished && !job_->compactness_queued)
                        queue_compactness(*job_);
                } catch (const Cancelled&) {
                }
            }
            lock.lock();
        } else if (view_.pending) {
            const bool current = job_ && job_->history && job_->generation == view_.generation;
            if (!current) view_.pending = false; // a stale request, or a job that failed
            const std::stop_token stop = job_stop_.get_token();
            lock.unlock();
            if (current) {
                try {
                    serve_view(*job_, stop, false);
                } catch (const Cancelled&) {
                } catch (const std::exception& e) {
                    post(job_->generation, FailedMessage{e.what()});
                }
            }
            lock.lock();
        } else if (measurer_hungry_) {
            measurer_hungry_ = false;
            const bool current = job_ && job_->history;
            lock.unlock();
            if (current) {
                try {
                    feed_measurer(*job_);
                } catch (const Cancelled&) {
                }
            }
            lock.lock();
        }
        working_ = false;
    }
}

void Worker::run_job(const JobRequest& request, std::uint64_t generation, std::stop_token stop) {
    ++jobs_started_;
    for (auto& f : progress_.fraction) f.store(0.0f);
    progress_.iteration.store(0);
    progress_.max_iterations.store(request.options.relax.max_iterations);
    progress_.generation.store(generation);
    job_ = std::make_unique<Job>();
    Job& job = *job_;
    job.generation = generation;
    job.stop = stop;
    try {
        // Open the input, unless it is the one already in memory.
        set_stage(generation, Stage::Load);
        if (!cached_source_ || !(cached_source_->spec == request.volume)) {
            cached_source_.reset();
            cached_closed_.reset();
            cached_mc_.reset();
            cached_source_ = std::make_shared<const Source>(
                open_source(request.volume, stage_progress(Stage::Load, stop)));
        }
        const float iso = request.iso.value_or(cached_source_->suggested_iso);
        job.source = cached_source_;
        if (request.close_border) {
            // One layer of outside around the grids, padded at this iso (core/closed_border.h).
            if (!cached_closed_ || cached_closed_iso_ != iso ||
                cached_closed_inside_ != request.options.inside) {
                cached_closed_.reset();
                cached_closed_ = std::make_shared<const Source>(
                    close_border(*cached_source_, iso, request.options.inside));
                cached_closed_iso_ = iso;
                cached_closed_inside_ = request.options.inside;
            }
            job.source = cached_closed_;
        }
        progress_.fraction[std::size_t(Stage::Load)].store(1.0f);
        const Volume& volume = *job.source->volume;
        const Segmentation* mask = job.source->mask.get();

        job.options = request.options;
        job.options.iso = iso;
        job.options.relax.iso = iso;
        // The phantom's exact surface at the phantom's own iso, else the first-order distance
        // to the chosen iso-surface of the grey values.
        const AccuracyReference reference = accuracy_reference(*job.source, iso);
        job.reference = reference.distance;
        job.options.measure.reference_volume = reference.volume;
        post(generation, VolumeMessage{job.source, iso, reference.analytic});

        // The topology: the label's mask, or the grey values thresholded, which Marching Cubes
        // and the net each classify as they are built (a byte a voxel would be 100 MiB on a
        // 512 x 512 x 400 CT, made before Marching Cubes and held to the end of the job).
        set_stage(generation, Stage::Segment);
        throw_if_stopped(stop);
        progress_.fraction[std::size_t(Stage::Segment)].store(1.0f);

        set_stage(generation, Stage::MarchingCubes);
        if (!cached_mc_ || cached_mc_iso_ != iso || cached_mc_inside_ != job.options.inside ||
            cached_mc_closed_ != request.close_border) {
            cached_mc_.reset();
            cached_mc_ = make_marching_cubes(job, volume, mask, stop);
            cached_mc_iso_ = iso;
            cached_mc_inside_ = job.options.inside;
            cached_mc_closed_ = request.close_border;
        }
        progress_.fraction[std::size_t(Stage::MarchingCubes)].store(1.0f);
        post(generation, MarchingCubesMessage{cached_mc_});

        // The net, relaxed by the pipeline itself; the worker watches every iteration.
        set_stage(generation, Stage::Net);
        const auto net_start = Clock::now();
        NetObserver observer;
        observer.on_net = [&](std::shared_ptr<const SurfaceNet> net,
                              std::shared_ptr<const GreyField> field) {
            throw_if_stopped(stop);
            auto context = std::make_shared<RelaxContext>();
            context->volume = job.source->volume;
            context->net = std::move(net);
            context->grey = std::move(field);
            context->options = job.options.relax;
            job.context = context;
            job.history =
                std::make_unique<IterationHistory>(job.context, options_.history_budget_bytes);
            progress_.fraction[std::size_t(Stage::Net)].store(1.0f);
            post(generation,
                 NetMessage{context->net->node_count(), context->net->link_count(),
                            context->net->quads.size(), job.options.relax.max_iterations,
                            ms_since(net_start), context});
            after_iteration(job, {}, 0.0f, stop); // iteration 0: the initial net
            set_stage(generation, Stage::Relax);
        };
        observer.on_iteration = [&](const RelaxIteration& it,
                                    std::span<const glm::vec3> positions) {
            after_iteration(job, positions, it.max_move, stop);
            return true;
        };
        observer.relax_progress = stage_progress(Stage::Relax, stop);
        MethodResult net = run_surface_net(volume, mask, job.options, job.reference,
                                           stage_progress(Stage::Net, stop), observer);
        const bool converged = net.metrics.converged;
        // The final mesh's distance to MC's surface, as the CLI's table reports it.
        net.metrics.to_marching_cubes = distance_to_mesh(net.mesh, cached_mc_->mesh, volume);
        auto final_frame = std::const_pointer_cast<DisplayMesh>(
            display_mesh(std::move(net), ++next_geometry_, job.history->latest_iteration()));
        final_frame->last = true;
        // The pipeline's mesh of the iteration the views already show (the quick frame, the
        // same triangles) keeps that frame's geometry: a clinical mesh is not drawn again.
        if (job.sent_frame && job.sent_frame->iteration == final_frame->iteration &&
            same_mesh(job.sent_frame->mesh, final_frame->mesh))
            final_frame->geometry = job.sent_frame->geometry;
        else
            note_index_changes(*final_frame, job.sent_frame.get());
        if (!job.preview)
            job.preview = std::make_shared<const PreviewMesh>(make_preview(final_frame->mesh));
        final_frame->preview = job.preview; // one per job: the views keep it
        job.final_frame = final_frame;
        serve_view(job, stop, true);
        set_stage(generation, Stage::Done);
        finish(job, 0, converged);
    } catch (const Cancelled&) {
        // A newer request (or shutdown) took over; it resets the progress itself.
    } catch (const std::exception& e) {
        set_stage(generation, Stage::Failed);
        post(generation, FailedMessage{e.what()});
    }
}

void Worker::relax_further(std::uint64_t generation, int extra, std::stop_token stop) {
    if (!job_ || !job_->history || job_->generation != generation) return;
    Job& job = *job_;
    try {
        set_stage(generation, Stage::Relax);
        const RelaxContext& c = *job.context;
        const int first = job.history->latest_iteration();
        extra = std::min(extra, std::numeric_limits<int>::max() - first);
        progress_.max_iterations.store(first + extra);
        job.final_frame.reset();
        job.done = false;
        job.compactness_queued = false; // the continuation's meshes get their own
        // relax() from the newest positions, the iterations numbered on (the damping schedule
        // goes on), so the history can recompute these iterations too.
        RelaxOptions options = c.options;
        options.max_iterations = first + extra;
        const RelaxResult relaxed =
            relax(*c.net, c.grey.get(), options,
                  [&](const RelaxIteration& it, std::span<const glm::vec3> positions) {
                      after_iteration(job, positions, it.max_move, stop);
                      return true;
                  },
                  stage_progress(Stage::Relax, stop), {job.history->latest(), first});
        const bool converged = relaxed.converged;
        serve_view(job, stop, true);
        set_stage(generation, Stage::Done);
        finish(job, first + 1, converged);
    } catch (const Cancelled&) {
    } catch (const std::exception& e) {
        set_stage(generation, Stage::Failed);
        post(generation, FailedMessage{e.what()});
    }
}

// The relaxation does not wait for the convergence numbers: the iteration is announced at once
// (the slider grows, the frame follows) and measured by the measurer once the job is done.
void Worker::after_iteration(Job& job, std::span<const glm::vec3> positions, float max_move,
                             std::stop_token stop) {
    throw_if_stopped(stop);
    if (!positions.empty()) job.history->append(positions);
    const int k = job.history->latest_iteration();
    job.max_moves.resize(std::size_t(k) + 1);
    job.max_moves[std::size_t(k)] = max_move;
    IterationStats stats;
    stats.iteration = k;
    stats.max_move = max_move;
    post(job.generation, IterationMessage{stats});
    progress_.iteration.store(k);
    serve_view(job, stop, false);
}

// Measures iterations [from, latest] on the measurer, then posts the end of the job: the
// FinishedMessage comes last, once every number of the job is in.
void Worker::finish(Job& job, int from, bool converged) {
    job.done = true;
    job.next_to_measure = from;
    job.finished = FinishedMessage{job.history->latest_iteration(), converged, 0.0};
    feed_measurer(job);
}

// Hands the measurer the next iterations, a few at a time (each holds a copy of the positions;
// a large net's whole history would not fit twice). The measurer asks for more when it takes one.
void Worker::feed_measurer(Job& job) {
    constexpr std::size_t kQueued = 2;
    const int latest = job.history->latest_iteration();
    while (job.next_to_measure <= latest) {
        {
            std::lock_guard lock(measure_mutex_);
            if (iteration_tasks_.size() >= kQueued) return;
        }
        const int k = job.next_to_measure++;
        auto positions =
            std::make_shared<const std::vector<glm::vec3>>(job.history->positions(k, job.stop));
        queue_iteration_measure(
            {job.stop, job.generation,
             [context = job.context, reference = job.reference, what = job.options.measure, k,
              max_move = job.max_moves[std::size_t(k)], positions]() -> std::optional<Payload> {
                 return IterationMessage{
                     measure_iteration(*context, reference, what, k, max_move, *positions)};
             }});
    }
    if (!job.finished) return;
    queue_iteration_measure(
        {job.stop, job.generation,
         [this, finished = *job.finished, start = job.start]() -> std::optional<Payload> {
             ++jobs_finished_;
             FinishedMessage f = finished;
             f.ms = ms_since(start);
             return f;
         }});
    job.finished.reset();
    if (job.compactness_wanted && !job.compactness_queued) queue_compactness(job);
}

// The compactness of the job's last meshes, after its FinishedMessage (empty when there is no
// mesh to reduce).
void Worker::queue_compactness(Job& job) {
    job.compactness_queued = true;
    const int last = job.history->latest_iteration();
    auto positions =
        std::make_shared<const std::vector<glm::vec3>>(job.history->positions(last, job.stop));
    const std::uint64_t geometry = next_geometry_ + 1;
    next_geometry_ += 2;
    queue_iteration_measure(
        {job.stop, job.generation,
         [context = job.context, reference = job.reference, what = job.options.measure,
          mc = cached_mc_, method = method_of(job.options.relax.mode), last, positions,
          geometry]() -> std::optional<Payload> {
             if (!mc) return CompactnessMessage{};
             return measure_compactness(*context, reference, what, *mc, method, last, *positions,
                                        geometry);
         }});
}

void Worker::serve_view(Job& job, std::stop_token stop, bool final_frame) {
    ViewRequest view;
    bool undrained = false;
    ShapeMeasure color_by = ShapeMeasure::Quality;
    {
        std::lock_guard lock(mutex_);
        view = view_;
        undrained = frame_undrained_;
        color_by = color_by_;
    }
    if (view.generation != job.generation) return;
    const int latest = job.history->latest_iteration();
    int target = -1;
    if (view.iteration == kLive) {
        // Following the relaxation: the newest iteration, once the UI took the last frame and
        // the pause after it is over (the relaxation's last iteration does not wait). The last
        // frame goes out measured even when its quick version went before.
        const bool paced =
            latest >= progress_.max_iterations.load() || Clock::now() >= job.next_live_frame;
        if (final_frame || view.pending || (!undrained && paced && job.frame_sent != latest))
            target = latest;
    } else if (view.pending) {
        target = std::min(view.iteration, latest);
    }
    if (target >= 0) {
        const Clock::time_point making = Clock::now();
        const bool recomputed = !job.history->stored(target);
        const std::vector<glm::vec3> positions = job.history->positions(target, stop);
        const auto frame = make_frame(job, target, positions);
        post(job.generation, FrameMessage{frame, recomputed});
        // A passing frame stops the relaxation while it is made, and the UI's upload and drawing
        // of it take the processor from the worker again: on the 512 x 512 x 400 CT one took
        // 100-190 ms while the UI drew, about an iteration's time, and with one every iteration
        // the relaxation took half as long again as without them. So the next waits: 8x the
        // making (4x gave 0.15 s more to the CT's comparison, as the window's drawing of each
        // frame in parts costs about as much processor time as the worker's making of it).
        if (view.iteration == kLive && !final_frame && !view.pending) {
            const Clock::time_point made = Clock::now();
            const std::chrono::duration<double> pause =
                std::min(std::chrono::duration<double>(made - making) * options_.live_frame_spacing,
                         std::chrono::duration<double>(std::chrono::hours(1)));
            job.next_live_frame = made + std::chrono::duration_cast<Clock::duration>(pause);
        }
        job.frame_sent = target;
        job.sent_frame = frame;
        if (is_distance(color_by) && cached_mc_) {
            throw_if_stopped(stop);
            // The grey iso and its inside, as the accuracy reference measures.
            auto pair = std::make_shared<const PairDistances>(
                pair_distances(color_by, cached_mc_->mesh, frame->mesh, *job.source->volume,
                               job.options.relax.iso, job.options.inside));
            post(job.generation,
                 DistanceMessage{std::move(pair), cached_mc_->geometry, frame->geometry, target});
        }
        // Frames passing by while following the relaxation are not measured; one asked for is,
        // once the user stays on it a moment (stepping quickly measures nothing in between).
        if (!frame->metrics_complete && (view.iteration != kLive || final_frame))
            queue_frame_measure(
                {stop, job.generation,
                 [context = job.context, reference = job.reference, what = job.options.measure,
                  frame, positions]() -> std::optional<Payload> {
                     const RelaxContext& c = *context;
                     Mesh mesh =
                         triangulate(*c.net, positions, c.options.triangulation, c.volume->spacing);
                     auto measured = frame->copy();
                     measured->metrics = measure_into_world(mesh, *c.volume, reference, what);
                     measured->metrics_complete = true;
                     return FrameMetricsMessage{measured};
                 },
                 Clock::now() + (final_frame ? Clock::duration::zero() : kDwell)});
    }
    if (view.pending) {
        std::lock_guard lock(mutex_);
        if (view_.serial == view.serial) view_.pending = false;
    }
}

std::span<const float> DisplayMesh::values(ShapeMeasure measure) const {
    return shapes.of(measure);
}

const MeasureSummary& DisplayMesh::summary(ShapeMeasure measure) const {
    static const MeasureSummary none;
    return is_distance(measure) ? none : summaries[std::size_t(measure)];
}

// The large arrays (mesh, shape measures, normals: 37 MB for a clinical mesh) in fresh storage on
// huge pages, where the struct's own copy faulted them 4 KiB at a time: 98 ms of the worker for
// the CT's Marching Cubes, before its metrics.
std::shared_ptr<DisplayMesh> DisplayMesh::copy() const {
    using detail::copy_on_huge_pages;
    const TriangleMeasures& s = shapes;
    return std::make_shared<DisplayMesh>(DisplayMesh{
        method, iteration,
        Mesh{copy_on_huge_pages(mesh.positions), copy_on_huge_pages(mesh.indices)},
        TriangleMeasures{copy_on_huge_pages(s.quality), copy_on_huge_pages(s.quality60),
                         copy_on_huge_pages(s.radius_ratio), copy_on_huge_pages(s.min_angle),
                         copy_on_huge_pages(s.max_angle)},
        summaries, copy_on_huge_pages(normals), metrics, metrics_complete, last, preview, geometry,
        changed_since, changed_runs});
}

void DisplayMesh::measure_triangles() {
    shapes = triangle_measures(mesh);
    for (const ShapeMeasure s :
         {ShapeMeasure::Quality, ShapeMeasure::Quality60, ShapeMeasure::RadiusRatio})
        summaries[std::size_t(s)] = summarize_measure(values(s));
}

// Marching Cubes as run_method makes and measures it, posted as soon as it is made and once more
// measured: on a clinical CT the metrics take ten times the mesh's build. Both share one geometry,
// so the views keep what they uploaded and drew.
std::shared_ptr<const DisplayMesh> Worker::make_marching_cubes(const Job& job, const Volume& volume,
                                                               const Segmentation* mask,
                                                               std::stop_token stop) {
    const auto start = Clock::now();
    Mesh index_mesh =
        marching_cubes_mesh(volume, mask, job.options, stage_progress(Stage::MarchingCubes, stop));
    const double ms = ms_since(start);
    throw_if_stopped(stop);
    auto quick = std::const_pointer_cast<DisplayMesh>(display_mesh(
        {Method::MarchingCubes, mesh_to_world(index_mesh, volume), {}}, ++next_geometry_));
    quick->metrics = quick_metrics(quick->mesh, quick->shapes.quality);
    quick->metrics.ms = ms;
    quick->metrics_complete = false;
    post(job.generation, MarchingCubesMessage{quick});
    throw_if_stopped(stop);
    auto measured = quick->copy();
    measured->metrics = measure_into_world(index_mesh, volume, job.reference, job.options.measure);
    measured->metrics.ms = ms;
    measured->metrics_complete = true;
    return measured;
}

// A quick frame: the mesh, its triangles' quality and normals; measured later on request.
std::shared_ptr<const DisplayMesh> Worker::make_frame(Job& job, int iteration,
                                                      std::span<const glm::vec3> positions) {
    if (job.final_frame && job.final_frame->iteration == iteration) return job.final_frame;
    const RelaxContext& c = *job.context;
    auto frame = std::make_shared<DisplayMesh>();
    frame->method = method_of(job.options.relax.mode);
    frame->iteration = iteration;
    frame->mesh = triangulate(*c.net, positions, c.options.triangulation, c.volume->spacing);
    place_in_world(frame->mesh, *c.volume);
    frame->measure_triangles();
    frame->normals = render::vertex_normals(frame->mesh);
    frame->metrics = quick_metrics(frame->mesh, frame->shapes.quality);
    frame->metrics_complete = false;
    frame->geometry = ++next_geometry_;
    note_index_changes(*frame, job.sent_frame.get());
    // The net's topology is the job's: one preview serves every iteration.
    if (!job.preview) job.preview = std::make_shared<const PreviewMesh>(make_preview(frame->mesh));
    frame->preview = job.preview;
    return frame;
}

} // namespace snert::app
