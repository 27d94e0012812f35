// Micro-benchmarks of the core passes on the sphere phantom: Marching Cubes, building the net,
// one relaxation iteration (with and without the mesh guard), triangulation. For profiling one
// pass with perf; `make bench` times whole stages with `snert bench`.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "core/marching_cubes.h"
#include "core/phantom.h"
#include "core/relaxation.h"
#include "core/surface_net.h"
#include "core/triangulation.h"

namespace {

// Phantoms are built once per size and shared by every benchmark.
const snert::Phantom& sphere(int size) {
    static std::map<int, std::unique_ptr<snert::Phantom>> cache;
    auto& slot = cache[size];
    if (!slot) slot = std::make_unique<snert::Phantom>(snert::make_phantom("sphere", size));
    return *slot;
}

void report_voxels(benchmark::State& state, const snert::Volume& volume) {
    state.counters["Mvoxels/s"] = benchmark::Counter(double(volume.voxel_count()) / 1e6,
                                                     benchmark::Counter::kIsIterationInvariantRate);
}

void BM_MarchingCubes(benchmark::State& state) {
    const snert::Phantom& p = sphere(int(state.range(0)));
    std::size_t triangles = 0;
    for (auto _ : state) {
        snert::Mesh mesh = snert::marching_cubes(p.volume, {p.iso, snert::InsideIs::Above});
        triangles = mesh.triangle_count();
        benchmark::DoNotOptimize(mesh.indices.data());
    }
    report_voxels(state, p.volume);
    state.counters["triangles"] = double(triangles);
}

void BM_SurfaceNetBuild(benchmark::State& state) {
    const snert::Phantom& p = sphere(int(state.range(0)));
    std::size_t nodes = 0;
    for (auto _ : state) {
        const snert::Segmentation s = snert::segment_threshold(p.volume, p.iso);
        snert::SurfaceNet net = snert::build_surface_net(s);
        nodes = net.node_count();
        benchmark::DoNotOptimize(net.links.data());
    }
    report_voxels(state, p.volume);
    state.counters["nodes"] = double(nodes);
}

// One SNERT iteration from the new net; range(1) 0: without the mesh guard (the paper's step).
void BM_RelaxStep(benchmark::State& state) {
    const snert::Phantom& p = sphere(int(state.range(0)));
    const snert::SurfaceNet net =
        snert::build_surface_net(snert::segment_threshold(p.volume, p.iso));
    snert::RelaxOptions options;
    options.iso = p.iso;
    options.keep_valid = state.range(1) != 0;
    const snert::GreyField grey = snert::make_grey_field(p.volume, options);
    std::vector<glm::vec3> next(net.node_count());
    for (auto _ : state) {
        benchmark::DoNotOptimize(snert::relax_step(net, &grey, options, 1, net.positions, next));
    }
    state.counters["Mnodes/s"] = benchmark::Counter(double(net.node_count()) / 1e6,
                                                    benchmark::Counter::kIsIterationInvariantRate);
    report_voxels(state, p.volume);
}

void BM_Triangulate(benchmark::State& state) {
    const snert::Phantom& p = sphere(int(state.range(0)));
    const snert::SurfaceNet net =
        snert::build_surface_net(snert::segment_threshold(p.volume, p.iso));
    for (auto _ : state) {
        snert::Mesh mesh = snert::triangulate(net, net.positions);
        benchmark::DoNotOptimize(mesh.indices.data());
    }
    state.counters["triangles"] = double(net.quads.size() * 2);
}

} // namespace

BENCHMARK(BM_MarchingCubes)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SurfaceNetBuild)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RelaxStep)
    ->Args({128, 1})
    ->Args({256, 1})
    ->Args({256, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_Triangulate)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
