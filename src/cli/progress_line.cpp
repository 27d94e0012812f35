// The progress line (contract: the header).
#include "progress_line.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>

namespace snert::cli {

struct ProgressLine::Line {
    std::string prefix; // "snert compare: "
    std::mutex mutex;
    std::string shown; // the text now on the line; empty: the line is clear

    // Redraws only when the text changes (whole percents), so a pass that reports per slice
    // costs a comparison, not a write.
    void show(const std::string& text) {
        std::lock_guard lock(mutex);
        if (text == shown) return;
        if (text.empty())
            std::fputs("\r\x1b[K", stderr);
        else
            std::fprintf(stderr, "\r%s%s\x1b[K", prefix.c_str(), text.c_str());
        std::fflush(stderr);
        shown = text;
    }
};

ProgressLine::ProgressLine(const std::string& command, bool quiet) {
    if (quiet || isatty(STDERR_FILENO) == 0) return;
    line_ = std::make_shared<Line>();
    line_->prefix = "snert " + command + ": ";
}

ProgressLine::~ProgressLine() {
    if (line_) line_->show({});
}

Progress ProgressLine::stage(const std::string& stage) const {
    Progress progress;
    if (!line_) return progress;
    progress.report = [line = line_, stage](float fraction) {
        if (!(fraction < 1.0f)) return line->show({});
        const int percent = int(std::floor(100.0f * std::max(fraction, 0.0f)));
        line->show(stage + " " + std::to_string(percent) + " %");
    };
    return progress;
}

CLI::Option* add_quiet_option(CLI::App& command, bool& quiet) {
    return command.add_flag("--quiet,-q", quiet,
                            "no progress line on standard error (shown only on a terminal)");
}

} // namespace snert::cli
