// snert: Marching Cubes and SNERT side by side. Dispatches to the subcommands; with none, opens
// the app where it is built in.
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "args.h"
#include "commands.h"
#include "core/progress.h"

namespace {

const char* kUsage =
    R"(usage: snert <command> [options]

commands:
  table1   the paper's Table 1 measured on the plane, sphere and two-spheres phantoms
  compare  Marching Cubes and the relaxed SurfaceNets of a volume, with all metrics
  export   write one method's mesh as STL, OBJ, PLY, OFF or VTK
)"
#ifdef SNERT_HAVE_RENDER
    R"(  render   draw the side-by-side comparison into a PNG, without a window
)"
#endif
#ifdef SNERT_HAVE_APP
    R"(  gui      open the interactive app (also: snert with no command)
)"
#endif
    R"(
inputs: phantom:NAME (plane, sphere, two-spheres, torus, noisy-sphere, binary-sphere) or a file
run `snert <command> --help` for the options of a command
)";

} // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty()) {
#ifdef SNERT_HAVE_APP
        args = {"gui"};
#else
        std::cerr << kUsage;
        return 2;
#endif
    }
    const std::string command = args.front();
    args.erase(args.begin());
    try {
        if (command == "--help" || command == "-h" || command == "help") {
            std::cout << kUsage;
            return 0;
        }
        if (command == "table1") return snert::cli::run_table1(args);
        if (command == "compare") return snert::cli::run_compare(args);
        if (command == "export") return snert::cli::run_export(args);
#ifdef SNERT_HAVE_RENDER
        if (command == "render") return snert::cli::run_render(args);
#endif
#ifdef SNERT_HAVE_APP
        if (command == "gui") return snert::cli::run_gui(args);
#endif
        throw snert::cli::UsageError("unknown command '" + command + "' (see snert --help)");
    } catch (const snert::cli::UsageError& e) {
        std::cerr << "snert " << command << ": " << e.what() << "\n";
        return 2;
    } catch (const std::invalid_argument& e) {
        std::cerr << "snert " << command << ": " << e.what() << "\n";
        return 2;
    } catch (const std::runtime_error& e) {
        // Bad input files and unwritable outputs: the message names the file.
        std::cerr << "snert " << command << ": " << e.what() << "\n";
        return 2;
    } catch (const snert::Cancelled&) {
        std::cerr << "snert " << command << ": cancelled\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "snert " << command << ": internal error: " << e.what() << "\n";
        return 1;
    }
}
