// snert bench: the pipeline's stages timed one by one, on the sphere phantom or a volume file,
// with a chosen number of threads: reading, Marching Cubes, building the net, one SNERT
// iteration, the metrics of a mesh, and the whole of `compare --mode snert`. `make bench` runs it
// beside VTK's flying edges and prints the ratios (bench/report.py).
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

#include "commands.h"
#include "freed_memory.h"
#include "core/mesh_guard.h"
#include "core/parallel.h"
#include "options.h"
#include "progress_line.h"
#include "report.h"

namespace snert::cli {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Processor time of all the process's threads (milliseconds): on a busy machine it changes
// less than wall time, so before/after comparisons of one pass use it.
double cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) / 1e6;
}

struct Timing {
    double ms = 0, cpu_ms = 0; // medians
};

// Medians of `repeat` timed runs of `run`.
template <class Run> Timing median_time(int repeat, const Run& run) {
    std::vector<double> wall, cpu;
    for (int r = 0; r < repeat; ++r) {
        const Clock::time_point start = Clock::now();
        const double cpu_start = cpu_ms();
        run();
        wall.push_back(ms_since(start));
        cpu.push_back(cpu_ms() - cpu_start);
    }
    std::sort(wall.begin(), wall.end());
    std::sort(cpu.begin(), cpu.end());
    return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

double peak_rss_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) / 1024.0; // kilobytes on Linux
}

struct Row {
    std::string stage;
    Timing time;
    std::string rate; // throughput, or what the time is per
};

} // namespace

Runner add_bench(CLI::App& app) {
    struct Args {
        int size = 256;
        std::string volume;
        float iso = 0.0f;
        CLI::Option* o_iso = nullptr;
        std::string isotropic;
        CLI::Option* o_isotropic = nullptr;
        unsigned threads = 0;
        int repeat = 3;
        bool close_border = false;
        PipelineArgs pipeline;
        std::string json;
        bool quiet = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* command = app.add_subcommand(
        "bench", "time the pipeline's stages on the sphere phantom or a volume file");
    command->footer("Times are wall clock, medians of --repeat runs (the whole comparison runs "
                    "once). The iteration is the first SNERT iterations from the new net.\n");
    CLI::Option* o_size = command->add_option("--size", args->size, "sphere phantom of N^3 voxels")
                              ->check(CLI::Range(8, 1024))
                              ->type_name("N")
                              ->capture_default_str();
    CLI::Option* o_volume =
        command->add_option("--volume", args->volume, "a volume file instead of the phantom")
            ->type_name("FILE")
            ->excludes(o_size);
    args->o_iso = command->add_option("--iso", args->iso, "the iso of --volume")
                      ->type_name("V")
                      ->needs(o_volume);
    args->o_isotropic = add_isotropic_option(*command, args->isotropic)->needs(o_volume);
    command->add_option("--threads", args->threads, "threads the passes may use (0: one per core)")
        ->check(CLI::Range(0u, 1024u))
        ->type_name("T")
        ->capture_default_str();
    command->add_option("--repeat", args->repeat, "runs per stage; the median is reported")
        ->check(CLI::Range(1, 100))
        ->type_name("R")
        ->capture_default_str();
    command->add_flag("--close-border,!--no-close-border", args->close_border,
                      "close the surfaces at the volume border first, as compare does with "
                      "--close-border (timed as a stage)");
    // The relaxation's options as compare takes them (the net is SNERT's).
    add_pipeline_options(*command, args->pipeline, false);
    add_json_option(*command, args->json);
    add_quiet_option(*command, args->quiet);
    return [args] {
        if (!args->json.empty() && args->json != "-") check_output(args->json, {".json"});
        const ThreadLimit limit(args->threads);
        InputChoice choice;
        choice.spec.input = args->volume.empty() ? "phantom:sphere" : args->volume;
        choice.spec.phantom_size = args->size;
        if (args->o_iso->count()) choice.iso = args->iso;
        choice.spec.isotropic = isotropic_edge(args->o_isotropic, args->isotropic);
        const ProgressLine progress("bench", args->quiet);

        std::vector<Row> rows;
        Source source;
        const Timing read =
            median_time(1, [&] { source = open_input(choice, progress.stage("reading")); });
        const float iso = choice.iso.value_or(source.suggested_iso);
        const InsideIs inside = source.suggested_inside;
        std::optional<Timing> closing;
        if (args->close_border)
            closing =
                median_time(1, [&] { source = close_border(std::move(source), iso, inside); });
        const Volume& volume = *source.volume;
        const double mvoxels = double(volume.voxel_count()) / 1e6;
        const auto per_second = [&](Timing t) {
            std::ostringstream text;
            text << std::fixed << std::setprecision(0) << mvoxels / (t.ms / 1e3) << " Mvoxels/s";
            return text.str();
        };
        rows.push_back({"read the volume", read, per_second(read)});
        if (closing) rows.push_back({"close the border", *closing, per_second(*closing)});

        progress.stage("Marching Cubes").update(0.0f);
        Mesh mc;
        const Timing mc_time = median_time(args->repeat, [&] {
            mc = Mesh{}; // the previous run's memory is not part of the peak
            mc = marching_cubes(volume, {iso, inside});
        });
        rows.push_back({"Marching Cubes", mc_time, per_second(mc_time)});
        // A stage again in memory that earlier runs used and freed, as in the app or a program
        // that extracts again: on a virtual machine a fresh page costs a fault of several
        // microseconds, more than Marching Cubes' work on it. An untimed first run fills the heap.
        const auto time_in_kept_memory = [&](const auto& make) {
            const KeepFreedMemory kept;
            auto result = make();
            return median_time(args->repeat, [&] {
                result = {};
                result = make();
            });
        };
        const Timing mc_kept_time = time_in_kept_memory([&] {
            return marching_cubes(volume, {iso, inside});
        });
        rows.push_back({"  in kept memory", mc_kept_time, per_second(mc_kept_time)});

        progress.stage("net").update(0.0f);
        std::unique_ptr<SurfaceNet> net;
        const Timing net_time = median_time(args->repeat, [&] {
            net.reset();
            net = std::make_unique<SurfaceNet>(build_surface_net(volume, iso, inside));
        });
        rows.push_back({"SurfaceNet build", net_time, per_second(net_time)});
        const Timing net_kept_time =
            time_in_kept_memory([&] { return build_surface_net(volume, iso, inside); });
        rows.push_back({"  in kept memory", net_kept_time, per_second(net_kept_time)});

        // Iterations 1, 2, ... from the new net, as compare runs them.
        progress.stage("SNERT iteration").update(0.0f);
        PipelineOptions pipeline = pipeline_options(args->pipeline, iso, inside);
        pipeline.relax.mode = RelaxMode::Snert;
        // Iterations 1 .. repeat of `options` from the net's positions, which end in `positions`.
        const auto time_iterations = [&](const RelaxOptions& options,
                                         std::vector<glm::vec3>& positions) {
            const GreyField grey = make_grey_field(volume, options);
            positions = net->positions;
            std::vector<glm::vec3> next(positions.size());
            MeshGuardScratch scratch; // as relax() keeps one for its steps
            int iteration = 0;
            return median_time(args->repeat, [&] {
                relax_step(*net, &grey, options, ++iteration, positions, next, nullptr, &scratch);
                positions.swap(next);
            });
        };
        std::vector<glm::vec3> positions;
        const Timing step = time_iterations(pipeline.relax, positions);
        const std::size_t nodes = net->node_count();
        const auto per_node = [&](Timing t) {
            return nodes > 0 ? t.ms * 1e6 / double(nodes) : 0.0;
        };
        const auto per_node_text = [&](Timing t) {
            std::ostringstream text;
            text << std::fixed << std::setprecision(0) << per_node(t) << " ns/node";
            return text.str();
        };
        const double ns_per_node = per_node(step);
        rows.push_back({"SNERT iteration", step, per_node_text(step)});
        // The same iterations with the other gradient of the two compared in `make bench`: the
        // trilinear field's own (8 samples a node) and central differences (the paper's, 56).
        const GradientMethod other = pipeline.relax.gradient == GradientMethod::Trilinear
                                         ? GradientMethod::Central
                                         : GradientMethod::Trilinear;
        RelaxOptions other_options = pipeline.relax;
        other_options.gradient = other;
        std::vector<glm::vec3> other_positions;
        const Timing other_step = time_iterations(other_options, other_positions);
        rows.push_back(
            {other == GradientMethod::Trilinear ? "  trilinear gradient" : "  central differences",
             other_step, per_node_text(other_step)});
        const bool chosen_trilinear = pipeline.relax.gradient == GradientMethod::Trilinear;
        const double trilinear_ns = chosen_trilinear ? ns_per_node : per_node(other_step);
        const double central_ns = chosen_trilinear ? per_node(other_step) : ns_per_node;

        // Every metric of the SNERT mesh, as compare measures it, and its distance to MC.
        progress.stage("metrics").update(0.0f);
        const Measured m = measured(source, iso);
        const Mesh relaxed =
            triangulate(*net, positions, pipeline.relax.triangulation, volume.spacing);
        const std::size_t triangles = relaxed.triangle_count();
        MeasureOptions what;
        what.reference_volume = m.reference.volume;
        const Timing metrics = median_time(
            args->repeat, [&] { measure(relaxed, volume, m.reference.distance, what); });
        const auto per_iteration = [&](Timing t) {
            std::ostringstream text;
            text << std::fixed << std::setprecision(1) << t.ms / step.ms << " iterations";
            return text.str();
        };
        rows.push_back({"metrics of the mesh", metrics, per_iteration(metrics)});
        const Mesh relaxed_world = mesh_to_world(relaxed, volume),
                   mc_world = mesh_to_world(mc, volume);
        const Timing to_mc =
            median_time(args->repeat, [&] { distance_to_mesh(relaxed_world, mc_world, volume); });
        rows.push_back({"distance to MC", to_mc, per_iteration(to_mc)});

        // What `snert compare --mode snert` does after reading: both methods, all metrics.
        net.reset();
        mc = Mesh{};
        const Timing compare = median_time(1, [&] {
            run_compared_methods(
                compared_methods(RelaxMode::Snert), source, pipeline, m,
                [&](Method method) { return progress.stage(std::string(label_of(method))); });
        });
        rows.push_back({"compare --mode snert", compare, per_second(compare)});
        progress.stage("").update(1.0f);

        const unsigned threads = thread_budget();
        const double peak = peak_rss_mb();
        std::ostream& table = args->json == "-" ? std::cerr : std::cout;
        table << source.title << ", iso " << format_number(iso) << ": " << nodes << " nodes, "
              << triangles << " SNERT triangles, " << threads << " thread"
              << (threads == 1 ? "" : "s") << ", peak " << std::fixed << std::setprecision(0)
              << peak << " MiB\n";
        table << std::left << std::setw(24) << "stage" << std::right << std::setw(10) << "ms"
              << std::setw(10) << "cpu ms"
              << "  rate\n";
        for (const Row& row : rows)
            table << std::left << std::setw(24) << row.stage << std::right << std::fixed
                  << std::setprecision(1) << std::setw(10) << row.time.ms << std::setw(10)
                  << row.time.cpu_ms << "  " << row.rate << "\n";

        if (!args->json.empty()) {
            nlohmann::json json = {{"input", choice.spec.input},
                                   {"iso", iso},
                                   {"size", {volume.dims.x, volume.dims.y, volume.dims.z}},
                                   {"threads", threads},
                                   {"repeat", args->repeat},
                                   {"load_ms", read.ms},
                                   {"mc_ms", mc_time.ms},
                                   {"mc_kept_ms", mc_kept_time.ms},
                                   {"net_ms", net_time.ms},
                                   {"net_kept_ms", net_kept_time.ms},
                                   {"relax_ms", step.ms},
                                   {"relax_cpu_ms", step.cpu_ms},
                                   {"relax_ns_per_node", ns_per_node},
                                   {"relax_trilinear_ns_per_node", trilinear_ns},
                                   {"relax_central_ns_per_node", central_ns},
                                   {"metrics_ms", metrics.ms},
                                   {"to_mc_ms", to_mc.ms},
                                   {"compare_ms", compare.ms},
                                   {"nodes", nodes},
                                   {"triangles", triangles},
                                   {"peak_rss_mb", peak}};
            write_json(args->json, json);
        }
        return 0;
    };
}

} // namespace snert::cli
