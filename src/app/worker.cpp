// The background worker: one thread, one job at a time, latest request wins.
//
// Locking: mutex_ guards only the hand-over fields (pending job, view request, outbox); it is
// never held while computing, so the UI thread's calls return at once. Everything the job
// computes lives in job_ and the caches, which only the worker thread touches.
#include "worker.h"

#include <chrono>
#include <exception>

#include "core/marching_cubes.h"
#include "core/triangulation.h"

namespace snert::app {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void throw_if_stopped(const std::stop_token& stop) {
    if (stop.stop_requested()) throw Cancelled();
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
    std::shared_ptr<const SourceVolume> source;
    PipelineOptions options;
    DistanceFunction reference;                  // voxel units; may be empty
    std::shared_ptr<const RelaxContext> context; // once the net exists
    std::unique_ptr<IterationHistory> history;
    int frame_sent = -1; // iteration of the last frame posted
};

Worker::Worker(WorkerOptions options)
    : options_(options), thread_([this](std::stop_token stop) { run(stop); }) {}

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
    view_ = {pending_generation_, kLive, false}; // a new job is followed live until told otherwise
    job_stop_.request_stop(); // the running job throws Cancelled at its next poll
    wake_.notify_one();
    return pending_generation_;
}

void Worker::show_iteration(std::uint64_t generation, int iteration) {
    std::lock_guard lock(mutex_);
    if (generation != latest_generation_) return;
    view_ = {generation, iteration < 0 ? kLive : iteration, true};
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

bool Worker::busy() const {
    std::lock_guard lock(mutex_);
    return working_ || pending_job_.has_value() || continue_request_.has_value() || view_.pending;
}

void Worker::post(std::uint64_t generation, Payload payload) {
    std::lock_guard lock(mutex_);
    if (std::holds_alternative<FrameMessage>(payload)) {
        frame_undrained_ = true;
        // A newer frame replaces one the UI has not taken yet: frames are views, not events.
        for (Message& m : outbox_) {
            if (m.generation == generation && std::holds_alternative<FrameMessage>(m.payload)) {
                m.payload = std::move(payload);
                return;
            }
        }
    }
    outbox_.push_back({generation, std::move(payload)});
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
    std::unique_lock lock(mutex_);
    while (!thread_stop.stop_requested()) {
        wake_.wait(lock, thread_stop, [this] {
            return pending_job_.has_value() || continue_request_.has_value() || view_.pending;
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
    try {
        // Load, unless the volume is the one already in memory.
        set_stage(generation, Stage::Load);
        if (!cached_source_ || !(cached_source_->spec == request.volume)) {
            cached_source_.reset();
            cached_mc_.reset();
            cached_source_ = std::make_shared<const SourceVolume>(
                load_source(request.volume, stage_progress(Stage::Load, stop)));
        }
        progress_.fraction[std::size_t(Stage::Load)].store(1.0f);
        job.source = cached_source_;
        const Volume& volume = *job.source->volume;

        const float iso = request.iso.value_or(job.source->suggested_iso);
        job.options = request.options;
        job.options.iso = iso;
        job.options.relax.iso = iso;
        // The phantom's exact surface is the reference only at the phantom's own iso; anywhere
        // else the first-order distance to the chosen iso-surface is.
        const bool analytic = job.source->analytic && iso == job.source->suggested_iso;
        job.reference = analytic ? job.source->reference : first_order_distance(volume, iso);
        post(generation, VolumeMessage{job.source, iso, analytic});

        set_stage(generation, Stage::Segment);
        throw_if_stopped(stop);
        const Segmentation segmentation = segment_threshold(volume, iso, job.options.inside);
        progress_.fraction[std::size_t(Stage::Segment)].store(1.0f);

        set_stage(generation, Stage::MarchingCubes);
        if (!cached_mc_ || cached_mc_iso_ != iso || cached_mc_inside_ != job.options.inside) {
            cached_mc_.reset();
            MethodResult mc = run_marching_cubes(volume, job.options, job.reference,
                                                 stage_progress(Stage::MarchingCubes, stop));
            auto display = std::make_shared<DisplayMesh>();
            display->method = mc.method;
            display->quality = triangle_quality(mc.mesh);
            display->mesh = std::move(mc.mesh);
            display->metrics = mc.metrics;
            cached_mc_ = std::move(display);
            cached_mc_iso_ = iso;
            cached_mc_inside_ = job.options.inside;
        }
        progress_.fraction[std::size_t(Stage::MarchingCubes)].store(1.0f);
        post(generation, MarchingCubesMessage{cached_mc_});

        set_stage(generation, Stage::Net);
        const auto net_start = Clock::now();
        auto context = std::make_shared<RelaxContext>();
        context->volume = job.source->volume;
        context->net = build_surface_net(segmentation, stage_progress(Stage::Net, stop));
        throw_if_stopped(stop);
        context->options = job.options.relax;
        context->grey = make_grey_field(*context->volume, context->options);
        job.context = context;
        job.history =
            std::make_unique<IterationHistory>(job.context, options_.history_budget_bytes);
        progress_.fraction[std::size_t(Stage::Net)].store(1.0f);
        post(generation, NetMessage{context->net.node_count(), context->net.link_count(),
                                    context->net.quads.size(), job.options.relax.max_iterations,
                                    ms_since(net_start)});
        after_iteration(job, {}, 0.0f, stop); // iteration 0: the initial net

        set_stage(generation, Stage::Relax);
        const RelaxResult relaxed = relax(
            context->net, &context->grey, context->options,
            [&](const RelaxIteration& it, std::span<const glm::vec3> positions) {
                after_iteration(job, positions, it.max_move, stop);
                return true;
            },
            stage_progress(Stage::Relax, stop));
        serve_view(job, stop, true);
        set_stage(generation, Stage::Done);
        ++jobs_finished_;
        post(generation, FinishedMessage{job.history->latest_iteration(), relaxed.converged,
                                         ms_since(job.start)});
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
        std::vector<glm::vec3> current(job.history->latest().begin(), job.history->latest().end());
        std::vector<glm::vec3> next(current.size());
        const int first = job.history->latest_iteration();
        progress_.max_iterations.store(first + extra);
        bool converged = false;
        for (int i = 0; i < extra && !converged; ++i) {
            throw_if_stopped(stop);
            // The same step relax() takes, so the history can recompute these iterations too.
            const float max_move =
                relax_step(c.net, &c.grey, c.options, first + i + 1, current, next);
            current.swap(next);
            after_iteration(job, current, max_move, stop);
            progress_.fraction[std::size_t(Stage::Relax)].store(float(i + 1) / float(extra));
            converged = max_move < c.options.epsilon;
        }
        serve_view(job, stop, true);
        set_stage(generation, Stage::Done);
        post(generation,
             FinishedMessage{job.history->latest_iteration(), converged, ms_since(job.start)});
    } catch (const Cancelled&) {
    } catch (const std::exception& e) {
        set_stage(generation, Stage::Failed);
        post(generation, FailedMessage{e.what()});
    }
}

void Worker::after_iteration(Job& job, std::span<const glm::vec3> positions, float max_move,
                             std::stop_token stop) {
    throw_if_stopped(stop);
    if (!positions.empty()) job.history->append(positions);
    const int k = job.history->latest_iteration();
    const RelaxContext& c = *job.context;
    const std::span<const glm::vec3> now = job.history->latest();

    // The convergence numbers, measured exactly as measure() does (core/pipeline.h).
    const Mesh index_mesh = triangulate(c.net, now, c.options.triangulation, c.volume->spacing);
    const Mesh world = mesh_to_world(index_mesh, *c.volume);
    IterationStats stats;
    stats.iteration = k;
    stats.max_move = max_move;
    const QualityStats quality = quality_stats(world);
    stats.quality_mean = quality.mean;
    stats.quality_min = quality.min;
    stats.smoothness = smoothness(world);
    if (job.reference) {
        const Accuracy a = accuracy(index_mesh, job.reference);
        stats.accuracy_vertices = a.vertices_mean;
        stats.accuracy_faces = a.faces_mean;
    }
    post(job.generation, IterationMessage{stats});
    progress_.iteration.store(k);
    serve_view(job, stop, false);
}

void Worker::serve_view(Job& job, std::stop_token stop, bool final_frame) {
    ViewRequest view;
    bool undrained = false;
    {
        std::lock_guard lock(mutex_);
        view = view_;
        undrained = frame_undrained_;
    }
    if (view.generation != job.generation) return;
    const int latest = job.history->latest_iteration();
    int target = -1;
    if (view.iteration == kLive) {
        // Following the relaxation: the newest iteration, once the UI took the last frame.
        const bool due = view.pending || final_frame || !undrained;
        if (due && job.frame_sent != latest)
            target = latest;
        else if (view.pending)
            target = latest;
    } else if (view.pending) {
        target = std::min(view.iteration, latest);
    }
    if (target >= 0) {
        const bool recomputed = !job.history->stored(target);
        const std::vector<glm::vec3> positions = job.history->positions(target, stop);
        post(job.generation, FrameMessage{make_frame(job, target, positions), recomputed});
        job.frame_sent = target;
    }
    if (view.pending) {
        std::lock_guard lock(mutex_);
        if (view_.generation == view.generation && view_.iteration == view.iteration)
            view_.pending = false;
    }
}

std::shared_ptr<const DisplayMesh> Worker::make_frame(const Job& job, int iteration,
                                                      std::span<const glm::vec3> positions) const {
    const RelaxContext& c = *job.context;
    const Mesh index_mesh =
        triangulate(c.net, positions, c.options.triangulation, c.volume->spacing);
    auto frame = std::make_shared<DisplayMesh>();
    frame->method = method_of(job.options.relax.mode);
    frame->iteration = iteration;
    frame->metrics = measure(index_mesh, *c.volume, job.reference);
    frame->mesh = mesh_to_world(index_mesh, *c.volume);
    frame->quality = triangle_quality(frame->mesh);
    return frame;
}

} // namespace snert::app
