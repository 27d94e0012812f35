// snert export: one method's mesh written as STL, OBJ, PLY, OFF or VTK, in world millimetres.
#include <iostream>

#include "commands.h"
#include "io/mesh_io.h"
#include "methods.h"

namespace snert::cli {

int run_export(const std::vector<std::string>& argv) {
    std::set<std::string> options = input_options();
    for (const auto& n : pipeline_option_names()) options.insert(n);
    options.insert("method");
    options.insert("out");
    const Args args(argv, options, input_switches());
    if (args.flag("help")) {
        std::cout << "usage: snert export VOLUME|phantom:NAME --method mc|sna|gradient|snert "
                     "--out FILE.{stl,obj,ply,off,vtk} [options of compare]\n";
        return 0;
    }
    const auto out = args.value("out");
    if (!out) throw UsageError("missing --out FILE.{stl,obj,ply,off,vtk}");
    const MeshFormat format = mesh_format_from_path(*out); // before the work: fail early
    if (args.has("mode")) throw UsageError("use --method to choose the mesh to export");
    const Method method = *parse_name<Method>(
        args.choice("method", "snert", {"mc", "sna", "gradient", "snert"}));
    const Input input = load_input(args);
    const MethodResult result = run_method(input, pipeline_options(args, input), method);
    require_surface(result, input);
    write_mesh(result.mesh, *out, format);
    std::cerr << "wrote " << *out << ": " << result.mesh.vertex_count() << " vertices, "
              << result.mesh.triangle_count() << " triangles (" << name_of(method) << ")\n";
    return 0;
}

} // namespace snert::cli
