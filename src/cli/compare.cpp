// snert compare: MC and the relaxed nets of one volume, all metrics, as a table and JSON.
#include <iostream>
#include <memory>

#include "commands.h"
#include "options.h"
#include "progress_line.h"
#include "report.h"

namespace snert::cli {

Runner add_compare(CLI::App& app) {
    struct Args {
        InputArgs input;
        PipelineArgs pipeline;
        std::string json;
        bool quiet = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* command = app.add_subcommand(
        "compare", "Marching Cubes and the relaxed SurfaceNets of a volume, with all metrics");
    add_input_options(*command, args->input);
    add_pipeline_options(*command, args->pipeline);
    add_json_option(*command, args->json);
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
        std::vector<MethodResult> results;
        nlohmann::json json;
        for (const Method method : compared_methods(args->pipeline.mode)) {
            results.push_back(run_source_method(method, source, pipeline, m,
                                                progress.stage(std::string(label_of(method)))));
            require_surface(results.back(), m);
        }
        measure_against_marching_cubes(results, *source.volume);
        for (const MethodResult& r : results)
            json[std::string(name_of(r.method))] = method_json(r, m);
        json["provenance"] =
            provenance_json("compare", input_json(source), iso, inside, pipeline.relax);
        json["provenance"]["iso_from"] = choice.iso ? "--iso" : source.iso_reason;
        std::ostream& table = args->json == "-" ? std::cerr : std::cout;
        print_table(table,
                    m.name + " (iso " + format_number(iso) +
                        (source.border_closed ? ", closed at the border)" : ")"),
                    results, m);
        if (!args->json.empty()) write_json(args->json, json);
        return 0;
    };
}

} // namespace snert::cli
