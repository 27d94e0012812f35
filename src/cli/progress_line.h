// Progress of a long command on standard error: one line ("snert compare: SNERT 42 %")
// redrawn in place while stderr is a terminal, and nothing at all when it is not (a log file, a
// pipe, CI) or when the command was given --quiet.
#pragma once

#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "core/progress.h"

namespace snert::cli {

class ProgressLine {
  public:
    // `command`: the subcommand's name; `quiet`: show nothing.
    ProgressLine(const std::string& command, bool quiet);
    ~ProgressLine(); // erases the line
    ProgressLine(const ProgressLine&) = delete;
    ProgressLine& operator=(const ProgressLine&) = delete;

    // A Progress that shows `stage` and its share done; reaching 1 erases the line, so
    // messages written between stages start on a clean line. Safe to call from any thread.
    Progress stage(const std::string& stage) const;

  private:
    struct Line;
    std::shared_ptr<Line> line_; // null when nothing is shown
};

// --quiet: no progress line.
CLI::Option* add_quiet_option(CLI::App& command, bool& quiet);

} // namespace snert::cli
