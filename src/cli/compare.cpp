// snert compare: MC and the relaxed nets of one volume, all metrics, as a table and JSON.
#include <iostream>
#include <memory>

#include "commands.h"
#include "compactness_report.h"
#include "options.h"
#include "progress_line.h"
#include "report.h"

namespace snert::cli {

Runner add_compare(CLI::App& app) {
    struct Args {
        InputArgs input;
        PipelineArgs pipeline;
        std::string json;
        EqualCountArgs equal_count;
        bool compactness = false;
        bool quiet = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* command = app.add_subcommand(
        "compare", "Marching Cubes and the relaxed SurfaceNets of a volume, with all metrics");
    add_input_options(*command, args->input);
    add_pipeline_options(*command, args->pipeline);
    add_json_option(*command, args->json);
    add_equal_count_option(*command, args->equal_count);
    command
        ->add_flag("--compactness,!--no-compactness", args->compactness,
                   "add each mesh's compactness curve (reduced to 50, 25, 10 and 5 % of its "
                   "triangles, its distance to the full mesh and its quality) to the JSON; it "
                   "costs several times the comparison on a large scan, so it is off by default")
        ->group("Compactness");
    add_quiet_option(*command, args->quiet);
    command->footer("The table goes to standard output (to standard error with --json -).\n");
    return [args] {
        const InputChoice choice = input_choice(args->input);
        if (!args->json.empty() && args->json != "-") check_output(args->json, {".json"});
        const ProgressLine progress("compare", args->quiet);
        Source source = open_input(choice, progress.stage("reading"));
        const float iso = choice.iso.value_or(source.suggested_iso);
        const InsideIs inside = choice.inside.value_or(source.suggested_inside);
        source = close_border_if_chosen(std::move(source), choice, iso, inside);
        const PipelineOptions pipeline = pipeline_options(args->pipeline, iso, inside);
        const Measured m = measured(source, iso);
        std::vector<MethodResult> results = run_compared_methods(
            compared_methods(args->pipeline.mode), source, pipeline, m,
            [&](Method method) { return progress.stage(std::string(label_of(method))); });
        nlohmann::json json;
        // The curve starts from the full meshes, before any equal-count reduction.
        std::vector<std::vector<CompactnessPoint>> curves;
        std::vector<Method> methods;
        if (!args->json.empty() && args->compactness) {
            const Progress curve_progress = progress.stage("compactness");
            for (std::size_t i = 0; i < results.size(); ++i) {
                curves.push_back(compactness_curve(results[i].mesh, *source.volume));
                methods.push_back(results[i].method);
                curve_progress.update(float(i + 1) / float(results.size()));
            }
            for (std::size_t i = 0; i < curves.size(); ++i)
                json["compactness"][std::string(name_of(methods[i]))] = compactness_json(curves[i]);
        }
        std::optional<EqualCountRun> equal;
        if (const auto request = equal_count_request(args->equal_count)) {
            equal = reduce_sources_to_equal_count(results, *request, source, pipeline, m);
            json["equal_count"] = equal_count_json(*equal);
        }
        for (std::size_t i = 0; i < results.size(); ++i) {
            nlohmann::json& j = json[std::string(name_of(results[i].method))];
            j = method_json(results[i], m);
            if (equal) j["decimation"] = decimation_json(equal->reports[i]);
        }
        json["provenance"] =
            provenance_json("compare", input_json(source), iso, inside, pipeline.relax);
        json["provenance"]["iso_from"] = choice.iso ? "--iso" : source.iso_reason;
        std::ostream& table = args->json == "-" ? std::cerr : std::cout;
        print_table(table,
                    m.name + " (iso " + format_number(iso) +
                        (source.border_closed ? ", closed at the border)" : ")"),
                    results, m);
        if (equal) print_equal_count(table, *equal, results);
        if (!curves.empty()) print_compactness(table, methods, curves);
        if (!args->json.empty()) write_json(args->json, json);
        return 0;
    };
}

} // namespace snert::cli
