// The subcommands of the `snert` executable. Each takes its arguments (after the subcommand
// name) and returns the process exit code; errors are thrown and mapped to codes by main.
#pragma once

#include <string>
#include <vector>

namespace snert::cli {

int run_table1(const std::vector<std::string>& args);
int run_compare(const std::vector<std::string>& args);
int run_export(const std::vector<std::string>& args);
#ifdef SNERT_HAVE_RENDER
int run_render(const std::vector<std::string>& args);
#endif
#ifdef SNERT_HAVE_APP
int run_gui(const std::vector<std::string>& args);
#endif

} // namespace snert::cli
