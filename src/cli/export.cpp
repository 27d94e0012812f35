// snert export: one method's mesh written as STL, OBJ, PLY, OFF, VTK (with per-triangle quality,
// angles and distance), Gmsh MSH or Abaqus INP, in world millimetres.
#include <iostream>
#include <memory>

#include "commands.h"
#include "core/input_error.h"
#include "io/mesh_export.h"
#include "options.h"
#include "progress_line.h"
#include "report.h"

namespace snert::cli {

Runner add_export(CLI::App& app) {
    struct Args {
        InputArgs input;
        PipelineArgs pipeline;
        Method method = Method::Snert;
        AbaqusElement element = AbaqusElement::S3;
        std::string out;
        bool quiet = false;
    };
    auto args = std::make_shared<Args>();
    CLI::App* command =
        app.add_subcommand("export", "write one method's mesh as STL, OBJ, PLY, OFF, VTK, "
                                     "Gmsh MSH 4.1 or Abaqus INP");
    add_input_options(*command, args->input);
    add_name_option(*command, "--method", args->method, "the mesh to write")->group("Output");
    command->add_option("--out", args->out, "the mesh file (world millimetres)")
        ->required()
        ->type_name("FILE.{stl,obj,ply,off,vtk,msh,inp}")
        ->group("Output");
    add_name_option(*command, "--abaqus-element", args->element,
                    "the element type of an .inp file: s3 (shell) or sfm3d3 (surface)")
        ->group("Output");
    // The net is chosen by --method: no --mode here.
    add_pipeline_options(*command, args->pipeline, false);
    add_quiet_option(*command, args->quiet);
    return [args] {
        const InputChoice choice = input_choice(args->input);
        try {
            mesh_format_from_path(args->out);
        } catch (const std::invalid_argument& e) {
            throw InputError(e.what());
        }
        check_output(args->out, {".stl", ".obj", ".ply", ".off", ".vtk", ".msh", ".inp"});
        const ProgressLine progress("export", args->quiet);
        Source source = open_input(choice, progress.stage("reading"));
        const float iso = choice.iso.value_or(source.suggested_iso);
        const InsideIs inside = choice.inside.value_or(source.suggested_inside);
        source = close_border_if_chosen(std::move(source), choice, iso, inside);
        const Measured m = measured(source, iso);
        const MethodResult result =
            run_source_method(args->method, source, pipeline_options(args->pipeline, iso, inside),
                              m, progress.stage(std::string(label_of(args->method))));
        require_surface(result, m);
        export_mesh(result.mesh, args->method, source, iso, args->out, args->element);
        std::cerr << "wrote " << args->out << ": " << result.mesh.vertex_count() << " vertices, "
                  << result.mesh.triangle_count() << " triangles (" << name_of(args->method)
                  << ")\n";
        return 0;
    };
}

} // namespace snert::cli
