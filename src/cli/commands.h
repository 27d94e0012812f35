// The subcommands of the `snert` executable. Each add_* declares its subcommand, with its
// options, on the CLI11 app and returns what runs it once the command line is parsed; the
// runner returns the exit code and throws for errors, which main maps to exit codes
// (InputError and CLI::ParseError: 2; anything else: 1).
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace snert::cli {

using Runner = std::function<int()>;

Runner add_table1(CLI::App& app);
Runner add_compare(CLI::App& app);
Runner add_export(CLI::App& app);
Runner add_bench(CLI::App& app);
#ifdef SNERT_HAVE_RENDER
Runner add_render(CLI::App& app);
#endif
#ifdef SNERT_HAVE_APP
Runner add_gui(CLI::App& app);
#endif

} // namespace snert::cli
