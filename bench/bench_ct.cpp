// Benchmarks on a CT volume, registered only when SNERT_BENCH_CT names one (`make bench` makes
// a 512 x 512 x 400 abdomen CT with ../shared/tools/upsample_ct.py): Marching Cubes at the
// bone (200) and skin (-500) isos, the net build, and one SNERT relaxation iteration (ns per
// node). Each is one pass per repetition, wall clock, median of the repetitions.
//
// Threads: src/core/parallel.h takes one thread per core (std::thread::hardware_concurrency)
// and has no knob for a caller, so these run with that default.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "core/marching_cubes.h"
#include "core/relaxation.h"
#include "core/surface_net.h"
#include "io/load_volume.h"

namespace {

const snert::Volume& ct_volume() {
    static std::unique_ptr<snert::Volume> volume;
    if (!volume)
        volume = std::make_unique<snert::Volume>(snert::load_volume(std::getenv("SNERT_BENCH_CT")));
    return *volume;
}

void report_voxels(benchmark::State& state, const snert::Volume& volume) {
    state.counters["Mvoxels/s"] = benchmark::Counter(double(volume.voxel_count()) / 1e6,
                                                     benchmark::Counter::kIsIterationInvariantRate);
}

void BM_CT_MarchingCubes(benchmark::State& state, float iso) {
    const snert::Volume& v = ct_volume();
    std::size_t triangles = 0;
    for (auto _ : state) {
        snert::Mesh mesh = snert::marching_cubes(v, {iso, snert::InsideIs::Above});
        triangles = mesh.triangle_count();
        benchmark::DoNotOptimize(mesh.indices.data());
    }
    report_voxels(state, v);
    state.counters["triangles"] = double(triangles);
}

void BM_CT_SurfaceNetBuild(benchmark::State& state, float iso) {
    const snert::Volume& v = ct_volume();
    std::size_t nodes = 0;
    for (auto _ : state) {
        const snert::Segmentation s = snert::segment_threshold(v, iso);
        snert::SurfaceNet net = snert::build_surface_net(s);
        nodes = net.node_count();
        benchmark::DoNotOptimize(net.links.data());
    }
    report_voxels(state, v);
    state.counters["nodes"] = double(nodes);
}

void BM_CT_RelaxStep(benchmark::State& state, float iso) {
    const snert::Volume& v = ct_volume();
    const snert::SurfaceNet net = snert::build_surface_net(snert::segment_threshold(v, iso));
    snert::RelaxOptions options;
    options.iso = iso;
    const snert::GreyField grey = snert::make_grey_field(v, options);
    std::vector<glm::vec3> next(net.node_count());
    for (auto _ : state) {
        benchmark::DoNotOptimize(snert::relax_step(net, &grey, options, 1, net.positions, next));
    }
    state.counters["nodes"] = double(net.node_count());
    // Inverted rate of nodes * 1e-9 per second: nanoseconds per node.
    state.counters["ns/node"] = benchmark::Counter(double(net.node_count()) * 1e-9,
                                                   benchmark::Counter::kIsIterationInvariantRate |
                                                       benchmark::Counter::kInvert);
}

bool register_ct() {
    const char* path = std::getenv("SNERT_BENCH_CT");
    if (!path || !*path) return false;
    for (const float iso : {200.0f, -500.0f}) {
        const std::string tag = "/iso:" + std::to_string(int(iso));
        auto setup = [](benchmark::internal::Benchmark* b, int repetitions) {
            b->Unit(benchmark::kMillisecond)
                ->UseRealTime()
                ->Iterations(1)
                ->Repetitions(repetitions)
                ->ReportAggregatesOnly(true);
        };
        setup(benchmark::RegisterBenchmark(("BM_CT_MarchingCubes" + tag).c_str(),
                                           BM_CT_MarchingCubes, iso),
              5);
        setup(benchmark::RegisterBenchmark(("BM_CT_SurfaceNetBuild" + tag).c_str(),
                                           BM_CT_SurfaceNetBuild, iso),
              3);
        setup(benchmark::RegisterBenchmark(("BM_CT_RelaxStep" + tag).c_str(), BM_CT_RelaxStep, iso),
              3);
    }
    return true;
}

const bool ct_registered = register_ct();

} // namespace
