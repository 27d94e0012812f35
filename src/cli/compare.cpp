// snert compare: MC and the relaxed nets of one volume, all metrics, as a table and JSON.
#include <iostream>

#include "commands.h"
#include "methods.h"

namespace snert::cli {

namespace {

const char* kHelp = R"(usage: snert compare VOLUME|phantom:NAME [options]

  --size N             phantom grid size (default 64)
  --iso V              iso value (default: the phantom's, or a suggestion for files)
  --inside above|below inside is I >= iso (default) or I <= iso
  --labels FILE --label N   segment by a label map; the net's gradient uses the grey image
  --mode sna|gradient|snert   run MC and this net only (default: MC, SNA and SNERT)
  --iterations K       relaxation iterations (default 20)
  --smoothing-weight W --gradient-weight W   weights of the two terms (default 1, 1)
  --schedule simultaneous|smoothing-first
  --constraint raybox|clip
  --gradient central|gaussian  --sigma S
  --epsilon E          stop when the largest move is under E voxels (default 1e-4)
  --triangulation shorter|delaunay
  --guard on|off       refuse moves that make the mesh self-intersect or add slivers (default on)
  --json FILE          also write the metrics as JSON
)";

} // namespace

int run_compare(const std::vector<std::string>& argv) {
    std::set<std::string> options = input_options();
    for (const auto& n : pipeline_option_names()) options.insert(n);
    options.insert("json");
    const Args args(argv, options, input_switches());
    if (args.flag("help")) {
        std::cout << kHelp;
        return 0;
    }
    const Input input = load_input(args);
    const PipelineOptions pipeline = pipeline_options(args, input);
    std::vector<MethodResult> results;
    nlohmann::json json;
    for (const Method method : requested_methods(args)) {
        results.push_back(run_method(input, pipeline, method));
        require_surface(results.back(), input);
        json[std::string(name_of(method))] = method_json(results.back(), input);
    }
    print_table(std::cout, input.name + " (iso " + std::to_string(input.iso) + ")", results, input);
    if (auto path = args.value("json")) write_json(*path, json);
    return 0;
}

} // namespace snert::cli
