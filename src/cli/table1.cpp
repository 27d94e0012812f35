// snert table1: the paper's Table 1 measured on the plane, sphere and two-spheres phantoms.
#include <iostream>

#include "commands.h"
#include "core/phantom.h"
#include "methods.h"

namespace snert::cli {

int run_table1(const std::vector<std::string>& argv) {
    std::set<std::string> options = pipeline_option_names();
    options.erase("mode");
    options.insert("size");
    options.insert("json");
    const Args args(argv, options, {"help"});
    if (args.flag("help")) {
        std::cout << "usage: snert table1 [--size N] [--json FILE] [relaxation options of "
                     "compare]\n";
        return 0;
    }
    if (!args.positional().empty())
        throw UsageError("unexpected argument '" + args.positional().front() + "'");
    const int size = args.integer("size", 64, 8, 1024);
    nlohmann::json json;
    for (const char* name : {"plane", "sphere", "two-spheres"}) {
        Phantom phantom = make_phantom(name, size);
        Input input;
        input.name = std::string("phantom:") + name;
        input.iso = phantom.iso;
        input.reference = phantom.reference_distance;
        input.analytic_reference = true;
        input.reference_volume = phantom.reference_volume;
        input.volume = std::move(phantom.volume);
        const PipelineOptions pipeline = pipeline_options(args, input);
        std::vector<MethodResult> results;
        std::string key = name;
        if (key == "two-spheres") key = "two_spheres";
        for (const Method method : {Method::MarchingCubes, Method::Sna, Method::Snert}) {
            results.push_back(run_method(input, pipeline, method));
            json[key][std::string(name_of(method))] = method_json(results.back(), input);
        }
        print_table(std::cout, input.name + " " + std::to_string(size) + "^3", results, input);
        std::cout << "\n";
    }
    std::cout
        << "q = smallest/largest angle (paper), q60 = smallest angle/60 deg, r_ratio = 2r/R;\n"
           "smooth = mean |2pi - angle sum| (rad); accV/accF = mean distance of vertices /"
           " face centres\nto the exact surface (voxels); vol_err = enclosed volume vs the"
           " exact one.\n";
    if (auto path = args.value("json")) write_json(*path, json);
    return 0;
}

} // namespace snert::cli
