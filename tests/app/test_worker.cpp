// The background worker: results equal the pipeline's, cancel/restart storms end with the last
// request's result, frames of any iteration on request, shutdown while busy.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <random>
#include <thread>

#include "app/job_results.h"
#include "app/worker.h"
#include "core/phantom.h"
#include "io/source.h"
#include "support/temp_folder.h"

using namespace snert;
using namespace snert::app;
using namespace std::chrono_literals;

namespace {

// Drains the worker into `results` (once per "frame", as the UI does) until `done` holds.
template <class Done>
bool pump_until(Worker& worker, JobResults& results, Done done,
                std::chrono::seconds timeout = 180s) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
        results.apply(worker.drain());
        if (done(results)) return true;
        std::this_thread::sleep_for(1ms);
    }
    return false;
}

bool finished(const JobResults& r) {
    return r.finished.has_value() || !r.error.empty();
}

// The compactness, asked for, comes after the FinishedMessage.
bool ended(const JobResults& r) {
    return r.compactness.has_value() || !r.error.empty();
}

// Drains the worker as fast as it can (no frame waits for the UI) until the job finishes, and
// returns the frames it posted, oldest first.
std::vector<std::shared_ptr<const DisplayMesh>> frames_until_finished(Worker& worker,
                                                                      JobResults& results) {
    std::vector<std::shared_ptr<const DisplayMesh>> frames;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!finished(results) && std::chrono::steady_clock::now() < deadline) {
        for (const Message& m : worker.drain()) {
            results.apply(m);
            if (const auto* f = std::get_if<FrameMessage>(&m.payload)) frames.push_back(f->mesh);
        }
    }
    return frames;
}

JobRequest phantom_job(const std::string& name, int size, std::optional<float> iso,
                       int iterations) {
    JobRequest job;
    job.volume = {"phantom:" + name, size};
    job.iso = iso;
    job.options.relax.max_iterations = iterations;
    return job;
}

// A phantom job whose relaxation runs every one of its iterations (no convergence test).
JobRequest all_iterations_job(const std::string& name, int size, int iterations) {
    JobRequest job = phantom_job(name, size, std::nullopt, iterations);
    job.options.relax.epsilon = 0.0f;
    return job;
}

// What the CLI computes for the same request (core/pipeline.h).
struct Expected {
    MethodResult mc, net;
};
Expected direct(const JobRequest& job) {
    const Phantom p = make_phantom(phantom_spec_name(job.volume.input), job.volume.phantom_size);
    PipelineOptions o = job.options;
    o.iso = o.relax.iso = job.iso.value_or(p.iso);
    const DistanceFunction reference =
        o.iso == p.iso ? p.reference_distance
                       : first_order_distance(std::make_shared<const Volume>(p.volume), o.iso);
    o.measure.reference_volume = o.iso == p.iso ? p.reference_volume : 0.0;
    Expected e;
    e.mc = run_marching_cubes(p.volume, o, reference);
    e.net = run_surface_net(p.volume, segment_threshold(p.volume, o.iso, o.inside), o, reference);
    return e;
}

// Every measured fact of two metrics, not the time or the relaxation's numbers.
void expect_same_measures(const MethodMetrics& a, const MethodMetrics& b) {
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.quality.mean, b.quality.mean);
    EXPECT_EQ(a.quality.min, b.quality.min);
    EXPECT_EQ(a.quality.quality60_mean, b.quality.quality60_mean);
    EXPECT_EQ(a.quality.radius_ratio_mean, b.quality.radius_ratio_mean);
    EXPECT_EQ(a.quality.min_angle_min, b.quality.min_angle_min);
    EXPECT_EQ(a.quality.degenerate, b.quality.degenerate);
    EXPECT_EQ(a.quality.slivers, b.quality.slivers);
    EXPECT_EQ(a.quality.histogram, b.quality.histogram);
    EXPECT_EQ(a.smoothness, b.smoothness);
    ASSERT_EQ(a.accuracy.has_value(), b.accuracy.has_value());
    if (a.accuracy) {
        EXPECT_EQ(a.accuracy->vertices_mean, b.accuracy->vertices_mean);
        EXPECT_EQ(a.accuracy->vertices_max, b.accuracy->vertices_max);
        EXPECT_EQ(a.accuracy->faces_mean, b.accuracy->faces_mean);
        EXPECT_EQ(a.accuracy->faces_max, b.accuracy->faces_max);
        EXPECT_EQ(a.accuracy->surface_mean, b.accuracy->surface_mean);
        EXPECT_EQ(a.accuracy->surface_max, b.accuracy->surface_max);
    }
    EXPECT_EQ(a.topology.watertight, b.topology.watertight);
    EXPECT_EQ(a.topology.manifold, b.topology.manifold);
    EXPECT_EQ(a.topology.oriented, b.topology.oriented);
    EXPECT_EQ(a.topology.euler, b.topology.euler);
    EXPECT_EQ(a.topology.boundary_edges, b.topology.boundary_edges);
    EXPECT_EQ(a.topology.nonmanifold_edges, b.topology.nonmanifold_edges);
    EXPECT_EQ(a.topology.nonmanifold_vertices, b.topology.nonmanifold_vertices);
    EXPECT_EQ(a.topology.collapsed_triangles, b.topology.collapsed_triangles);
    EXPECT_EQ(a.boundary_edges_off_border, b.boundary_edges_off_border);
    EXPECT_EQ(a.self_intersections, b.self_intersections);
    EXPECT_EQ(a.fe_ready, b.fe_ready);
    EXPECT_EQ(a.area, b.area);
    EXPECT_EQ(a.volume, b.volume);
    EXPECT_EQ(a.volume_error, b.volume_error);
}

void expect_matches_pipeline(const JobResults& r, const JobRequest& job) {
    const Expected e = direct(job);
    ASSERT_TRUE(r.mc && r.frame);
    EXPECT_TRUE(r.mc_current && r.frame_current && r.source_current);
    EXPECT_TRUE(same_mesh(r.mc->mesh, e.mc.mesh));
    EXPECT_EQ(r.mc->shapes.quality.size(), e.mc.mesh.triangle_count());
    EXPECT_EQ(r.mc->metrics.quality.mean, e.mc.metrics.quality.mean);
    EXPECT_TRUE(same_mesh(r.frame->mesh, e.net.mesh));
    EXPECT_EQ(r.frame->metrics.quality.mean, e.net.metrics.quality.mean);
    EXPECT_EQ(r.frame->metrics.smoothness, e.net.metrics.smoothness);
    expect_same_measures(r.mc->metrics, e.mc.metrics);
    expect_same_measures(r.frame->metrics, e.net.metrics);
    EXPECT_EQ(r.frame->method, e.net.method);
    ASSERT_TRUE(r.finished);
    EXPECT_EQ(r.frame->iteration, r.finished->iterations);
}

void expect_consecutive_iterations(const JobResults& r) {
    ASSERT_TRUE(r.finished);
    ASSERT_EQ(r.iteration_count(), r.finished->iterations + 1);
    for (int k = 0; k < r.iteration_count(); ++k)
        EXPECT_EQ(r.iterations[std::size_t(k)].iteration, k);
}

} // namespace

TEST(Worker, OneJobGivesThePipelinesResult) {
    Worker worker;
    JobResults r;
    const JobRequest job = phantom_job("sphere", 24, std::nullopt, 10);
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    ASSERT_TRUE(r.error.empty()) << r.error;
    expect_matches_pipeline(r, job);
    expect_consecutive_iterations(r);
    EXPECT_EQ(r.iso, 0.0f);
    EXPECT_TRUE(r.analytic_reference);
    ASSERT_TRUE(r.source);
    EXPECT_EQ(r.source->volume->dims, glm::ivec3(24));
    EXPECT_EQ(r.source->histogram.total(), std::uint64_t(24 * 24 * 24));
    EXPECT_FALSE(r.source->mask);
    ASSERT_TRUE(r.net);
    EXPECT_EQ(r.net->nodes, r.frame->mesh.vertex_count());
    EXPECT_EQ(r.net->quads * 2, r.frame->mesh.triangle_count());
    // Iteration 0 is the initial net; relaxation improves the quality (paper table 1).
    EXPECT_GT(r.iterations.back().quality_mean, r.iterations.front().quality_mean);
    EXPECT_EQ(r.iterations.front().max_move, 0.0f);
    EXPECT_GE(r.iterations.back().accuracy_vertices, 0.0);
    EXPECT_EQ(worker.progress().generation.load(), r.generation);
    EXPECT_EQ(worker.progress().stage.load(), int(Stage::Done));
    EXPECT_EQ(worker.progress().fraction[std::size_t(Stage::MarchingCubes)].load(), 1.0f);
    EXPECT_FALSE(worker.busy());
}

// The window sleeps between its few frames while the worker computes: every result posted calls
// on_message, after it can be drained, so the results wake the window at once. An iteration's
// numbers do not: the window's next progress frame takes them.
TEST(Worker, EveryResultCallsOnMessage) {
    std::atomic<int> calls{0};
    WorkerOptions options;
    options.on_message = [&] { ++calls; };
    Worker worker(options);
    JobResults r;
    r.start(worker.request(phantom_job("sphere", 24, std::nullopt, 6)));
    int results = 0, numbers = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!finished(r) && std::chrono::steady_clock::now() < deadline) {
        for (const Message& m : worker.drain()) {
            const bool result = wakes_the_window(m.payload);
            EXPECT_EQ(result, !std::holds_alternative<IterationMessage>(m.payload));
            (result ? results : numbers) += 1;
            r.apply(m);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(finished(r));
    EXPECT_GT(results, 0);
    EXPECT_GE(numbers, 2 * 7); // iterations 0-6 announced, then measured
    // The call follows the message's posting by a moment: wait for the last one.
    for (int k = 0; k < 1000 && calls.load() < results; ++k)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_GE(calls.load(), results); // a frame replacing one not yet drained calls it too
    // Had the numbers called it too, there would be a call for every message drained.
    EXPECT_LT(calls.load(), results + numbers);
    EXPECT_FALSE(worker.has_results());
}

// Hundreds of parameter changes, some mid-job, some while draining: no deadlock, and what the
// UI ends up showing is exactly the last request's result.
TEST(Worker, CancelRestartStormEndsWithTheLastRequest) {
    Worker worker;
    JobResults r;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> iso(-1.5f, 1.5f);
    const RelaxMode modes[] = {RelaxMode::Averaging, RelaxMode::Gradient, RelaxMode::Snert};
    JobRequest last;
    std::size_t stale = 0, current = 0;
    constexpr int kRequests = 300;
    for (int i = 0; i < kRequests; ++i) {
        JobRequest job = phantom_job(i % 4 == 0 ? "two-spheres" : "sphere", 18 + int(rng() % 3) * 3,
                                     iso(rng), 4 + int(rng() % 8));
        job.options.relax.mode = modes[rng() % 3];
        job.options.inside = rng() % 5 == 0 ? InsideIs::Below : InsideIs::Above;
        r.start(worker.request(job));
        ASSERT_EQ(r.generation, std::uint64_t(i + 1));
        last = job;
        if (i % 7 == 0) std::this_thread::sleep_for(std::chrono::microseconds(rng() % 3000));
        if (i % 3 == 0) {
            for (const Message& m : worker.drain()) (r.apply(m) ? current : stale) += 1;
        }
        if (i % 11 == 0 && i + 1 < kRequests) worker.show_iteration(r.generation, int(rng() % 5));
    }
    ASSERT_TRUE(pump_until(worker, r, finished)) << "the last job never finished";
    ASSERT_TRUE(r.error.empty()) << r.error;
    EXPECT_EQ(r.generation, std::uint64_t(kRequests));
    EXPECT_LE(worker.jobs_started(), std::uint64_t(kRequests));
    EXPECT_GE(worker.jobs_started(), 1u);
    expect_matches_pipeline(r, last);
    expect_consecutive_iterations(r);
    EXPECT_EQ(r.iso, *last.iso);
    // Nothing arrives after the last job's end.
    std::this_thread::sleep_for(20ms);
    EXPECT_EQ(r.apply(worker.drain()), 0);
    EXPECT_FALSE(worker.busy());
    EXPECT_FALSE(worker.has_messages());
    std::cout << "[          ] " << worker.jobs_started() << " of " << kRequests
              << " jobs started, " << stale << " stale messages dropped\n";
}

// Frames of any iteration, recomputed from keyframes when the budget holds none of them.
TEST(Worker, ShowsAnyIterationOnRequest) {
    WorkerOptions options;
    options.history_budget_bytes = 0;
    Worker worker(options);
    JobResults r;
    JobRequest job = all_iterations_job("two-spheres", 24, 12);
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    ASSERT_EQ(r.finished->iterations, 12);
    for (int k : {5, 0, 6, 12, 3}) {
        worker.show_iteration(r.generation, k);
        ASSERT_TRUE(pump_until(worker, r, [k](const JobResults& x) {
            return x.frame && x.frame->iteration == k && x.frame->metrics_complete;
        })) << k;
        JobRequest upto = job;
        upto.options.relax.max_iterations = k;
        EXPECT_TRUE(same_mesh(r.frame->mesh, direct(upto).net.mesh)) << k;
        EXPECT_EQ(r.frame_recomputed, k != 0 && k != 12) << k;
        EXPECT_EQ(r.frame->metrics.quality.mean, r.iterations[std::size_t(k)].quality_mean);
    }
    // Beyond the end: clamped to the last iteration.
    worker.show_iteration(r.generation, 99);
    ASSERT_TRUE(pump_until(worker, r, [](const JobResults& x) {
        return x.frame->iteration == 12 && !x.frame_recomputed;
    }));
    // A request for an older job is ignored.
    worker.show_iteration(r.generation - 1, 2);
    std::this_thread::sleep_for(20ms);
    EXPECT_EQ(r.apply(worker.drain()), 0);
}

TEST(Worker, RelaxesFurtherOnRequest) {
    Worker worker;
    JobResults r;
    JobRequest job = phantom_job("sphere", 20, std::nullopt, 3);
    job.options.relax.epsilon = 1e-3f;
    job.options.relax.damping_start = 5; // the continuation crosses it: iterations number on
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    ASSERT_EQ(r.finished->iterations, 3);
    ASSERT_FALSE(r.finished->converged);
    r.finished.reset();
    worker.continue_relaxation(r.generation, 200);
    ASSERT_TRUE(pump_until(worker, r, finished));
    const int n = r.finished->iterations;
    EXPECT_GT(n, 3);
    expect_consecutive_iterations(r);
    if (r.finished->converged)
        EXPECT_LT(r.iterations.back().max_move, 1e-3f);
    else
        EXPECT_EQ(n, 203);
    // The same positions as one relaxation of n iterations.
    JobRequest all = job;
    all.options.relax.max_iterations = n;
    all.options.relax.epsilon = 0.0f;
    EXPECT_TRUE(same_mesh(r.frame->mesh, direct(all).net.mesh));
    EXPECT_EQ(r.frame->iteration, n);
}

TEST(Worker, ReportsBadInputAndRecovers) {
    Worker worker;
    JobResults r;
    r.start(worker.request(phantom_job("no-such-phantom", 16, std::nullopt, 2)));
    ASSERT_TRUE(pump_until(worker, r, finished));
    EXPECT_NE(r.error.find("no-such-phantom"), std::string::npos) << r.error;
    EXPECT_EQ(worker.progress().stage.load(), int(Stage::Failed));

    JobRequest missing;
    missing.volume = {"/nonexistent/volume.nrrd", 64};
    r.start(worker.request(missing));
    ASSERT_TRUE(pump_until(worker, r, finished));
    EXPECT_NE(r.error.find("/nonexistent/volume.nrrd"), std::string::npos) << r.error;

    const JobRequest good = phantom_job("sphere", 16, std::nullopt, 2);
    r.start(worker.request(good));
    ASSERT_TRUE(pump_until(worker, r, finished));
    EXPECT_TRUE(r.error.empty()) << r.error;
    expect_matches_pipeline(r, good);
}

// Destroying a worker in the middle of a long job returns promptly (the job is cancelled).
TEST(Worker, ShutsDownWhileBusy) {
    for (int i = 0; i < 20; ++i) {
        const auto start = std::chrono::steady_clock::now();
        {
            Worker worker;
            JobRequest job = all_iterations_job("torus", 48, 100000);
            worker.request(job);
            std::this_thread::sleep_for(std::chrono::milliseconds(i * 3));
        }
        EXPECT_LT(std::chrono::steady_clock::now() - start, 20s);
    }
}

// Changing only a relaxation parameter keeps the volume and the Marching Cubes mesh.
TEST(Worker, ReusesVolumeAndMarchingCubes) {
    Worker worker;
    JobResults r;
    JobRequest job = phantom_job("sphere", 20, std::nullopt, 3);
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    const auto source = r.source;
    const auto mc = r.mc;
    job.options.relax.mode = RelaxMode::Averaging;
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    EXPECT_EQ(r.source, source);
    EXPECT_EQ(r.mc, mc);
    EXPECT_EQ(r.frame->method, Method::Sna);
    job.iso = 0.5f;
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    EXPECT_EQ(r.source, source);
    EXPECT_NE(r.mc, mc);
    EXPECT_FALSE(r.analytic_reference);
    expect_matches_pipeline(r, job);
}

// Closing the border (io/source.h) gives the CLI's closed meshes; turning it off again gives
// the open ones back, Marching Cubes included (its cache knows the difference).
TEST(Worker, ClosesTheBorderLikeTheCommandLine) {
    Worker worker;
    JobResults r;
    JobRequest job = phantom_job("plane", 16, std::nullopt, 5);
    job.close_border = true;
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    ASSERT_TRUE(r.error.empty()) << r.error;
    ASSERT_TRUE(r.mc && r.frame && r.source);
    EXPECT_TRUE(r.source->border_closed);
    EXPECT_EQ(r.source->volume->dims, glm::ivec3(18));
    for (const DisplayMesh* m : {r.mc.get(), r.frame.get()}) {
        EXPECT_TRUE(m->metrics.topology.watertight);
        EXPECT_TRUE(m->metrics.topology.manifold);
        EXPECT_EQ(m->metrics.topology.euler, 2);
        EXPECT_TRUE(m->metrics.fe_ready);
    }
    // The same meshes as close_border + run_method, as `snert compare --close-border` runs.
    const Source closed = close_border(open_source(job.volume), 0.0f, InsideIs::Above);
    PipelineOptions o = job.options;
    const AccuracyReference reference = accuracy_reference(closed, 0.0f);
    o.measure.reference_volume = reference.volume;
    const MethodResult mc =
        run_method(Method::MarchingCubes, *closed.volume, nullptr, o, reference.distance);
    const MethodResult net =
        run_method(Method::Snert, *closed.volume, nullptr, o, reference.distance);
    EXPECT_TRUE(same_mesh(r.mc->mesh, mc.mesh));
    EXPECT_TRUE(same_mesh(r.frame->mesh, net.mesh));
    expect_same_measures(r.mc->metrics, mc.metrics);
    expect_same_measures(r.frame->metrics, net.metrics);

    job.close_border = false;
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    ASSERT_TRUE(r.mc && r.frame && r.source);
    EXPECT_FALSE(r.source->border_closed);
    EXPECT_FALSE(r.mc->metrics.topology.watertight);
    EXPECT_FALSE(r.frame->metrics.topology.watertight);
    expect_matches_pipeline(r, job);
}

// The frames' metrics are measure()'s of the same mesh (core/pipeline.h), at an iteration the
// worker triangulates itself and at the last one, which the pipeline made; the convergence
// numbers of every iteration are measure()'s too.
TEST(Worker, FrameMetricsAreThoseOfMeasure) {
    Worker worker;
    JobResults r;
    JobRequest job = all_iterations_job("two-spheres", 22, 6);
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    ASSERT_TRUE(r.error.empty()) << r.error;
    ASSERT_EQ(r.finished->iterations, 6);

    const Phantom p = make_phantom("two-spheres", 22);
    RelaxOptions relax_options = job.options.relax;
    relax_options.iso = p.iso;
    const SurfaceNet net = build_surface_net(segment_threshold(p.volume, p.iso));
    const GreyField field = make_grey_field(p.volume, relax_options);
    MeasureOptions what;
    what.reference_volume = p.reference_volume;
    for (int k : {6, 2, 0}) {
        worker.show_iteration(r.generation, k);
        ASSERT_TRUE(pump_until(worker, r, [k](const JobResults& x) {
            return x.frame && x.frame->iteration == k && x.frame->metrics_complete;
        })) << k;
        RelaxOptions upto = relax_options;
        upto.max_iterations = k;
        const RelaxResult relaxed = relax(net, &field, upto);
        const Mesh index_mesh =
            triangulate(net, relaxed.positions, upto.triangulation, p.volume.spacing);
        const MethodMetrics expected = measure(index_mesh, p.volume, p.reference_distance, what);
        SCOPED_TRACE(k);
        expect_same_measures(r.frame->metrics, expected);
        ASSERT_TRUE(r.frame->metrics.volume_error.has_value());
        EXPECT_LT(std::abs(*r.frame->metrics.volume_error), 0.1);
        const IterationStats& stats = r.iterations[std::size_t(k)];
        EXPECT_EQ(stats.quality_mean, expected.quality.mean);
        EXPECT_EQ(stats.quality_min, expected.quality.min);
        EXPECT_EQ(stats.smoothness, expected.smoothness);
        EXPECT_EQ(stats.accuracy_vertices, expected.accuracy->vertices_mean);
        EXPECT_EQ(stats.accuracy_faces, expected.accuracy->faces_mean);
    }
    ASSERT_TRUE(r.mc);
    ASSERT_TRUE(r.mc->metrics.volume_error.has_value());
    EXPECT_LT(std::abs(*r.mc->metrics.volume_error), 0.05);
}

namespace {

// A float NRRD of `volume`'s samples (unit spacing), or of its samples as uint8 labels.
void write_nrrd(const std::string& path, const Volume& volume, bool labels) {
    std::string text = std::string("NRRD0004\ntype: ") + (labels ? "uint8" : "float") +
                       "\ndimension: 3\nsizes: " + std::to_string(volume.dims.x) + " " +
                       std::to_string(volume.dims.y) + " " + std::to_string(volume.dims.z) +
                       "\nspacings: 1 1 1\nendian: little\nencoding: raw\n\n";
    for (const float v : volume.samples) {
        if (labels) {
            text.push_back(char(std::uint8_t(v)));
        } else {
            char bytes[sizeof(float)];
            std::memcpy(bytes, &v, sizeof v);
            text.append(bytes, sizeof bytes);
        }
    }
    test::write_text(path, text);
}

} // namespace

// With a label map and a label, the methods run as the CLI runs them: Marching Cubes on the
// label's mask at 0.5 (run_method), the net with the mask as its topology and the grey values
// in the gradient term.
TEST(Worker, LabelMaskJobRunsTheMethodsOnTheMask) {
    const test::TempFolder folder("snert-worker");
    const Phantom p = make_phantom("sphere", 22);
    // Labels: 1 in a ball a little smaller than the grey sphere, 2 in a slab, 0 elsewhere.
    Volume labels = p.volume;
    const glm::vec3 centre = glm::vec3(p.volume.dims - 1) * 0.5f;
    for (int z = 0; z < labels.dims.z; ++z)
        for (int y = 0; y < labels.dims.y; ++y)
            for (int x = 0; x < labels.dims.x; ++x) {
                const float d = glm::length(glm::vec3(x, y, z) - centre);
                labels.samples[labels.index(x, y, z)] = d < 6.3f ? 1.0f : z < 3 ? 2.0f : 0.0f;
            }
    const std::string grey_path = folder.file("grey.nrrd"),
                      labels_path = folder.file("labels.nrrd");
    write_nrrd(grey_path, p.volume, false);
    write_nrrd(labels_path, labels, true);

    Worker worker;
    JobResults r;
    JobRequest job;
    job.volume.input = grey_path;
    job.volume.labels = labels_path;
    job.volume.label = 1;
    job.options.relax.max_iterations = 5;
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    ASSERT_TRUE(r.error.empty()) << r.error;
    ASSERT_TRUE(r.source && r.source->mask && r.mc && r.frame);
    EXPECT_FALSE(r.analytic_reference);

    const Source source = open_source(job.volume);
    ASSERT_TRUE(source.mask);
    EXPECT_EQ(r.iso, source.suggested_iso);
    PipelineOptions o = job.options;
    o.iso = o.relax.iso = source.suggested_iso;
    const AccuracyReference reference = accuracy_reference(source, o.iso);
    const MethodResult mc =
        run_method(Method::MarchingCubes, *source.volume, source.mask.get(), o, reference.distance);
    const MethodResult net = run_method(method_of(o.relax.mode), *source.volume, source.mask.get(),
                                        o, reference.distance);
    EXPECT_TRUE(same_mesh(r.mc->mesh, mc.mesh));
    expect_same_measures(r.mc->metrics, mc.metrics);
    EXPECT_TRUE(same_mesh(r.frame->mesh, net.mesh));
    expect_same_measures(r.frame->metrics, net.metrics);
    // Marching Cubes of the mask itself, not of the grey values at the iso.
    const Volume mask = mask_volume(*source.mask, *source.volume);
    EXPECT_TRUE(same_mesh(r.mc->mesh, mesh_to_world(marching_cubes(mask, {0.5f}), mask)));
    const Mesh grey_mc = mesh_to_world(
        marching_cubes(*source.volume, {source.suggested_iso, source.suggested_inside}),
        *source.volume);
    EXPECT_FALSE(same_mesh(r.mc->mesh, grey_mc));
}

// The relaxation does not wait for its numbers: each iteration is announced (largest move
// only) as it finishes and measured afterwards; the end of the job comes after every number.
TEST(Worker, IterationsAreAnnouncedThenMeasuredThenTheJobEnds) {
    Worker worker;
    JobResults r;
    JobRequest job = all_iterations_job("sphere", 24, 6);
    r.start(worker.request(job));
    std::vector<Message> all;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!r.finished && r.error.empty() && std::chrono::steady_clock::now() < deadline) {
        for (Message& m : worker.drain()) {
            r.apply(m);
            all.push_back(std::move(m));
        }
        std::this_thread::sleep_for(1ms);
    }
    ASSERT_TRUE(r.finished);
    std::vector<int> announced(7, -1), measured(7, -1);
    int position = 0, finished_at = -1, last_frame_at = -1;
    for (const Message& m : all) {
        if (const auto* it = std::get_if<IterationMessage>(&m.payload)) {
            auto& slot = it->stats.measured ? measured : announced;
            slot[std::size_t(it->stats.iteration)] = position;
        } else if (std::holds_alternative<FinishedMessage>(m.payload)) {
            finished_at = position;
        } else if (const auto* f = std::get_if<FrameMessage>(&m.payload)) {
            if (f->mesh->last) last_frame_at = position;
        }
        ++position;
    }
    for (std::size_t k = 0; k < 7; ++k) {
        EXPECT_GE(announced[k], 0) << k;
        EXPECT_GT(measured[k], announced[k]) << k;
        EXPECT_GT(finished_at, measured[k]) << k;
        EXPECT_TRUE(r.iterations[k].measured) << k;
    }
    // Only the compactness of the last meshes may follow the end of the job.
    for (std::size_t i = std::size_t(finished_at) + 1; i < all.size(); ++i)
        EXPECT_TRUE(std::holds_alternative<CompactnessMessage>(all[i].payload)) << i;
    ASSERT_GE(last_frame_at, 0);
    EXPECT_TRUE(r.frame->last && r.frame->metrics_complete);
}

// While the views follow the relaxation, a frame waits live_frame_spacing times the last one's
// making after it: with a spacing no run reaches, the initial net's frame is the only one passing
// by until the last iteration's (which never waits, when the UI has taken the one before), then
// the final one. Without the wait, nearly every iteration of this net has a frame.
TEST(Worker, FollowingFramesWaitAfterTheLastOne) {
    WorkerOptions options;
    options.live_frame_spacing = 1e6;
    Worker worker(options);
    JobResults r;
    JobRequest job = all_iterations_job("sphere", 48, 8);
    r.start(worker.request(job));
    const auto frames = frames_until_finished(worker, r);
    ASSERT_TRUE(r.finished);
    ASSERT_GE(frames.size(), 2u);
    ASSERT_LE(frames.size(), 3u);
    EXPECT_EQ(frames.front()->iteration, 0);
    EXPECT_TRUE(frames.back()->last);
    EXPECT_EQ(frames.back()->iteration, 8);
    if (frames.size() == 3) {
        EXPECT_EQ(frames[1]->iteration, 8);
    }
    // Stepping is not paced: a frame asked for comes at once.
    worker.show_iteration(r.generation, 3);
    ASSERT_TRUE(pump_until(worker, r,
                           [](const JobResults& x) { return x.frame && x.frame->iteration == 3; }));
}

// A frame asked for comes at once, unmeasured, then measured with the same geometry (which
// the views do not upload again); the quick one has the normals and the preview's share.
TEST(Worker, AskedFrameComesQuickThenMeasured) {
    Worker worker;
    JobResults r;
    JobRequest job = all_iterations_job("two-spheres", 24, 5);
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    worker.show_iteration(r.generation, 2);
    std::shared_ptr<const DisplayMesh> quick, measured;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!measured && std::chrono::steady_clock::now() < deadline) {
        for (const Message& m : worker.drain()) {
            r.apply(m);
            if (const auto* f = std::get_if<FrameMessage>(&m.payload)) quick = f->mesh;
            if (const auto* f = std::get_if<FrameMetricsMessage>(&m.payload)) measured = f->mesh;
        }
        std::this_thread::sleep_for(1ms);
    }
    ASSERT_TRUE(quick && measured);
    EXPECT_FALSE(quick->metrics_complete);
    EXPECT_EQ(quick->iteration, 2);
    EXPECT_EQ(quick->normals.size(), quick->mesh.vertex_count());
    EXPECT_EQ(quick->metrics.triangles, quick->mesh.triangle_count());
    EXPECT_TRUE(measured->metrics_complete);
    EXPECT_EQ(measured->geometry, quick->geometry);
    EXPECT_EQ(r.frame, measured); // it replaced the quick one it belongs to
    EXPECT_EQ(measured->metrics.quality.mean, r.iterations[2].quality_mean);
    // Everything but the metrics is the quick frame's, copied.
    EXPECT_NE(measured->mesh.positions.data(), quick->mesh.positions.data());
    EXPECT_TRUE(same_mesh(measured->mesh, quick->mesh));
    EXPECT_EQ(measured->shapes.quality, quick->shapes.quality);
    EXPECT_EQ(measured->shapes.quality60, quick->shapes.quality60);
    EXPECT_EQ(measured->shapes.radius_ratio, quick->shapes.radius_ratio);
    EXPECT_EQ(measured->shapes.min_angle, quick->shapes.min_angle);
    EXPECT_EQ(measured->shapes.max_angle, quick->shapes.max_angle);
    EXPECT_EQ(measured->normals, quick->normals);
    EXPECT_EQ(measured->method, quick->method);
    EXPECT_EQ(measured->iteration, quick->iteration);
    EXPECT_EQ(measured->last, quick->last);
    EXPECT_EQ(measured->preview, quick->preview);
    EXPECT_EQ(measured->changed_since, quick->changed_since);
    EXPECT_EQ(measured->changed_runs.size(), quick->changed_runs.size());
    for (std::size_t k = 0; k < quick->summaries.size(); ++k)
        EXPECT_EQ(measured->summaries[k].mean, quick->summaries[k].mean);
    // A measured frame of another geometry does not replace the one shown.
    auto other = std::make_shared<DisplayMesh>(*measured);
    other->geometry = measured->geometry + 1000;
    r.apply(Message{r.generation, FrameMetricsMessage{other}});
    EXPECT_EQ(r.frame, measured);
}

// Each frame made for the views carries the runs of its indices that differ from the frame sent
// before it, as the UI would compare them, so that the UI thread need not.
TEST(Worker, FramesCarryTheIndexRunsThatChangedSinceTheFrameBefore) {
    Worker worker;
    JobResults r;
    JobRequest job = all_iterations_job("two-spheres", 32, 8);
    r.start(worker.request(job));
    std::vector<std::shared_ptr<const DisplayMesh>> frames;
    const auto collect = [&](const std::function<bool()>& done) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
        while (!done() && r.error.empty() && std::chrono::steady_clock::now() < deadline) {
            for (const Message& m : worker.drain()) {
                r.apply(m);
                if (const auto* f = std::get_if<FrameMessage>(&m.payload))
                    frames.push_back(f->mesh);
            }
            std::this_thread::sleep_for(1ms);
        }
        return done();
    };
    ASSERT_TRUE(collect([&] { return finished(r); }));
    // Back to the first iteration and forward again: the largest changes of the triangulation.
    for (const int iteration : {0, 8, 1}) {
        worker.show_iteration(r.generation, iteration);
        ASSERT_TRUE(
            collect([&] { return !frames.empty() && frames.back()->iteration == iteration; }));
    }
    std::size_t compared = 0, changed = 0;
    for (std::size_t k = 1; k < frames.size(); ++k) {
        const DisplayMesh& frame = *frames[k];
        if (frame.changed_since == 0) continue;
        ++compared;
        EXPECT_EQ(frame.changed_since, frames[k - 1]->geometry) << k;
        EXPECT_EQ(frame.changed_runs,
                  render::changed_index_runs(frame.mesh.indices, frames[k - 1]->mesh.indices))
            << k;
        changed += frame.changed_runs.empty() ? 0 : 1;
    }
    EXPECT_GE(compared, 3u);
    EXPECT_GE(changed, 1u) << "some step splits a quad along its other diagonal";
}

// Marching Cubes goes out as soon as it is made, before the net, and again once measured: the
// same geometry, the same mesh, the pipeline's metrics on the second.
TEST(Worker, MarchingCubesComesQuickThenMeasured) {
    Worker worker;
    JobResults r;
    const JobRequest job = phantom_job("two-spheres", 24, std::nullopt, 3);
    r.start(worker.request(job));
    std::vector<std::shared_ptr<const DisplayMesh>> mc;
    bool net_before_measured = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (!finished(r) && std::chrono::steady_clock::now() < deadline) {
        for (const Message& m : worker.drain()) {
            r.apply(m);
            if (const auto* f = std::get_if<MarchingCubesMessage>(&m.payload))
                mc.push_back(f->mesh);
            if (std::holds_alternative<NetMessage>(m.payload) && mc.size() < 2)
                net_before_measured = true;
        }
        std::this_thread::sleep_for(1ms);
    }
    ASSERT_TRUE(r.finished);
    ASSERT_EQ(mc.size(), 2u);
    EXPECT_FALSE(net_before_measured);
    const DisplayMesh &quick = *mc[0], &measured = *mc[1];
    EXPECT_FALSE(quick.metrics_complete);
    EXPECT_TRUE(measured.metrics_complete);
    EXPECT_EQ(quick.geometry, measured.geometry);
    EXPECT_TRUE(same_mesh(quick.mesh, measured.mesh));
    EXPECT_EQ(quick.metrics.triangles, quick.mesh.triangle_count());
    EXPECT_EQ(quick.normals.size(), quick.mesh.vertex_count());
    ASSERT_TRUE(quick.preview);
    EXPECT_EQ(quick.preview, measured.preview);
    EXPECT_NEAR(quick.metrics.quality.mean, measured.metrics.quality.mean, 1e-6);
    EXPECT_FALSE(quick.metrics.accuracy); // not measured yet
    EXPECT_EQ(r.mc, mc[1]);
    expect_same_measures(measured.metrics, direct(job).mc.metrics);
}

// The pipeline's mesh of the last iteration is the quick frame of that iteration, measured: when
// that frame went out, the last one keeps its geometry (the views do not draw it again).
TEST(Worker, LastFrameKeepsTheGeometryOfItsQuickFrame) {
    Worker worker;
    int seen = 0;
    for (int attempt = 0; attempt < 5 && seen == 0; ++attempt) {
        JobResults r;
        JobRequest job = all_iterations_job("sphere", 40, 4);
        r.start(worker.request(job));
        const auto frames = frames_until_finished(worker, r); // every frame is taken at once
        ASSERT_TRUE(r.finished && r.frame);
        ASSERT_TRUE(r.frame->last && r.frame->metrics_complete);
        EXPECT_TRUE(r.frame->metrics.to_marching_cubes);
        for (const auto& f : frames) {
            if (f->last || f->iteration != r.frame->iteration) continue;
            ++seen;
            EXPECT_FALSE(f->metrics_complete);
            EXPECT_EQ(f->geometry, r.frame->geometry);
            EXPECT_TRUE(same_mesh(f->mesh, r.frame->mesh));
            // The quick frame's measurement, arriving late, does not replace the last frame.
            auto measured = std::make_shared<DisplayMesh>(*f);
            measured->metrics_complete = true;
            const auto last = r.frame;
            r.apply(Message{r.generation, FrameMetricsMessage{measured}});
            EXPECT_EQ(r.frame, last);
        }
    }
    EXPECT_GT(seen, 0) << "the quick frame of the last iteration never went out";
}

// After the job, the measurer reduces the last meshes: the compactness curves and the pair at
// one triangle count, measured again, as the CLI's compare --equal-count does.
TEST(Worker, CompactnessFollowsTheJob) {
    Worker worker;
    JobResults r;
    r.start(worker.request(phantom_job("sphere", 32, std::nullopt, 5)));
    worker.want_compactness(r.generation); // before the job is done: made once it is
    ASSERT_TRUE(pump_until(worker, r, ended));
    ASSERT_TRUE(r.finished);
    const CompactnessMessage& c = *r.compactness;
    ASSERT_EQ(c.mc_curve.size(), kCompactnessFractions.size());
    ASSERT_EQ(c.net_curve.size(), kCompactnessFractions.size());
    EXPECT_EQ(c.mc_curve.front().triangles, r.mc->mesh.triangle_count());
    EXPECT_EQ(c.net_curve.front().triangles, r.frame->mesh.triangle_count());
    EXPECT_GT(c.net_curve.back().accuracy_mean, c.net_curve[1].accuracy_mean);
    EXPECT_EQ(c.equal_count, std::min(r.mc->mesh.triangle_count(), r.frame->mesh.triangle_count()));
    for (const auto& mesh : {c.mc_equal, c.net_equal}) {
        ASSERT_TRUE(mesh);
        EXPECT_LE(mesh->mesh.triangle_count(), c.equal_count);
        EXPECT_GE(double(mesh->mesh.triangle_count()), 0.99 * double(c.equal_count));
        EXPECT_EQ(mesh->metrics.triangles, mesh->mesh.triangle_count());
        EXPECT_EQ(mesh->shapes.quality.size(), mesh->mesh.triangle_count());
        EXPECT_EQ(mesh->normals.size(), mesh->mesh.vertex_count());
        EXPECT_TRUE(mesh->metrics.fe_ready);
    }
    EXPECT_EQ(c.net_equal->iteration, r.frame->iteration);
    EXPECT_NE(c.mc_equal->geometry, c.net_equal->geometry);
    EXPECT_NE(c.net_equal->geometry, r.frame->geometry);

    // Not asked for: none. Asked for after the end: made then.
    r.start(worker.request(phantom_job("sphere", 24, std::nullopt, 3)));
    ASSERT_TRUE(pump_until(worker, r, finished));
    std::this_thread::sleep_for(50ms);
    r.apply(worker.drain());
    EXPECT_FALSE(r.compactness);
    worker.want_compactness(r.generation);
    ASSERT_TRUE(pump_until(worker, r, ended));
    EXPECT_EQ(r.compactness->net_curve.front().triangles, r.frame->mesh.triangle_count());
}

namespace {
bool distances_of_frame(const JobResults& r, ShapeMeasure measure, int iteration) {
    return r.frame && r.frame->iteration == iteration && r.distances &&
           r.distances->distances->measure == measure && r.distances->iteration == iteration &&
           r.distances->net_geometry == r.frame->geometry &&
           r.distances->mc_geometry == r.mc->geometry;
}
} // namespace

// Distances cost: none is measured until one is chosen; then the frame shown is served again
// with them, each frame asked for after it gets its own (pair_distances of the two meshes), and
// none once a shape is chosen again.
TEST(Worker, DistancesOnlyWhileChosenAndForTheFrameShown) {
    Worker worker;
    JobResults r;
    JobRequest job = all_iterations_job("sphere", 24, 6);
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    ASSERT_TRUE(pump_until(worker, r, [](const JobResults& x) { return x.frame != nullptr; }));
    EXPECT_FALSE(r.distances);

    worker.set_color_by(ShapeMeasure::DistanceOther);
    ASSERT_TRUE(pump_until(worker, r, [](const JobResults& x) {
        return distances_of_frame(x, ShapeMeasure::DistanceOther, 6);
    }));
    const Volume& volume = *r.source->volume;
    const PairDistances expected = pair_distances(ShapeMeasure::DistanceOther, r.mc->mesh,
                                                  r.frame->mesh, volume, r.iso, InsideIs::Above);
    EXPECT_EQ(r.distances->distances->first, expected.first);
    EXPECT_EQ(r.distances->distances->second, expected.second);
    EXPECT_EQ(r.distances->distances->scale.high, expected.scale.high);

    worker.set_color_by(ShapeMeasure::DistanceIso);
    worker.show_iteration(r.generation, 2);
    ASSERT_TRUE(pump_until(worker, r, [](const JobResults& x) {
        return distances_of_frame(x, ShapeMeasure::DistanceIso, 2);
    }));
    EXPECT_EQ(r.distances->distances->second,
              signed_iso_distances(r.frame->mesh, volume, r.iso, InsideIs::Above));

    // Back to a shape: frames come without distances.
    worker.set_color_by(ShapeMeasure::Quality);
    const auto before = r.distances->distances;
    worker.show_iteration(r.generation, 4);
    ASSERT_TRUE(pump_until(worker, r, [](const JobResults& x) {
        return x.frame && x.frame->iteration == 4 && x.frame->metrics_complete;
    }));
    EXPECT_EQ(r.distances->distances, before);
}
