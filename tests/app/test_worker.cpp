// The background worker: results equal the pipeline's, cancel/restart storms end with the last
// request's result, frames of any iteration on request, shutdown while busy.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <random>
#include <thread>

#include "app/job_results.h"
#include "app/worker.h"
#include "core/phantom.h"

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

JobRequest phantom_job(const std::string& name, int size, std::optional<float> iso,
                       int iterations) {
    JobRequest job;
    job.volume = {"phantom:" + name, size};
    job.iso = iso;
    job.options.relax.max_iterations = iterations;
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
        o.iso == p.iso ? p.reference_distance : first_order_distance(p.volume, o.iso);
    Expected e;
    e.mc = run_marching_cubes(p.volume, o, reference);
    e.net = run_surface_net(p.volume, segment_threshold(p.volume, o.iso, o.inside), o, reference);
    return e;
}

bool same_mesh(const Mesh& a, const Mesh& b) {
    return a.positions.size() == b.positions.size() && a.indices == b.indices &&
           std::memcmp(a.positions.data(), b.positions.data(),
                       a.positions.size() * sizeof(glm::vec3)) == 0;
}

void expect_matches_pipeline(const JobResults& r, const JobRequest& job) {
    const Expected e = direct(job);
    ASSERT_TRUE(r.mc && r.frame);
    EXPECT_TRUE(r.mc_current && r.frame_current && r.source_current);
    EXPECT_TRUE(same_mesh(r.mc->mesh, e.mc.mesh));
    EXPECT_EQ(r.mc->quality.size(), e.mc.mesh.triangle_count());
    EXPECT_EQ(r.mc->metrics.quality.mean, e.mc.metrics.quality.mean);
    EXPECT_TRUE(same_mesh(r.frame->mesh, e.net.mesh));
    EXPECT_EQ(r.frame->metrics.quality.mean, e.net.metrics.quality.mean);
    EXPECT_EQ(r.frame->metrics.smoothness, e.net.metrics.smoothness);
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
    float total = 0;
    for (float c : r.source->histogram.counts) total += c;
    EXPECT_EQ(total, 24.0f * 24 * 24);
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
    JobRequest job = phantom_job("two-spheres", 24, std::nullopt, 12);
    job.options.relax.epsilon = 0.0f;
    r.start(worker.request(job));
    ASSERT_TRUE(pump_until(worker, r, finished));
    ASSERT_EQ(r.finished->iterations, 12);
    for (int k : {5, 0, 6, 12, 3}) {
        worker.show_iteration(r.generation, k);
        ASSERT_TRUE(pump_until(worker, r, [k](const JobResults& x) {
            return x.frame && x.frame->iteration == k;
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
            JobRequest job = phantom_job("torus", 48, std::nullopt, 100000);
            job.options.relax.epsilon = 0.0f;
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
