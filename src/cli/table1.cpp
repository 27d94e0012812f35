// snert table1: the paper's Table 1 measured on the plane, sphere and two-spheres phantoms.
#include <iostream>
#include <memory>

#include "commands.h"
#include "options.h"
#include "progress_line.h"
#include "report.h"

namespace snert::cli {

Runner add_table1(CLI::App& app) {
    struct Args {
        int size = 64;
        PipelineArgs pipeline;
        std::string json;
        bool quiet = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* command = app.add_subcommand(
        "table1", "the paper's Table 1 measured on the plane, sphere and two-spheres phantoms");
    command->add_option("--size", args->size, "phantom grid size N (N^3 voxels)")
        ->check(CLI::Range(8, 1024))
        ->type_name("N")
        ->capture_default_str();
    // Table 1 compares MC, SNA and SNERT: no --mode.
    add_pipeline_options(*command, args->pipeline, false);
    add_json_option(*command, args->json);
    add_quiet_option(*command, args->quiet);
    return [args] {
        if (!args->json.empty() && args->json != "-") check_output(args->json, {".json"});
        std::ostream& table = args->json == "-" ? std::cerr : std::cout;
        nlohmann::json json;
        nlohmann::json phantoms = nlohmann::json::array();
        const ProgressLine progress("table1", args->quiet);
        for (const char* name : {"plane", "sphere", "two-spheres"}) {
            InputChoice choice;
            choice.spec.input = std::string("phantom:") + name;
            choice.spec.phantom_size = args->size;
            const Source source = open_input(choice);
            const float iso = source.suggested_iso;
            const PipelineOptions pipeline =
                pipeline_options(args->pipeline, iso, source.suggested_inside);
            const Measured m = measured(source, iso);
            std::string key = name;
            if (key == "two-spheres") key = "two_spheres";
            const std::vector<MethodResult> results = run_compared_methods(
                compared_methods(std::nullopt), source, pipeline, m, [&](Method method) {
                    return progress.stage(std::string(name) + " " + std::string(label_of(method)));
                });
            for (const MethodResult& r : results)
                json[key][std::string(name_of(r.method))] = method_json(r, m);
            nlohmann::json entry = input_json(source);
            entry["iso"] = iso;
            phantoms.push_back(std::move(entry));
            print_table(table, m.name + " " + std::to_string(args->size) + "^3", results, m);
            table << "\n";
        }
        json["provenance"] =
            provenance_json("table1", {{"phantoms", phantoms}}, std::nullopt, std::nullopt,
                            pipeline_options(args->pipeline, 0.0f, InsideIs::Above).relax);
        if (!args->json.empty()) write_json(args->json, json);
        return 0;
    };
}

} // namespace snert::cli
