// Completion of a path typed into the app's "Open" field, against the files that exist.
//
// GL-free. "~/" is expanded to $HOME. Hidden entries (names starting with '.') are offered
// only when the typed name starts with '.'. Folders are listed with a trailing '/', so
// accepting one continues into it.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace snert::app {

struct PathCompletion {
    std::string completed;               // the input extended by the candidates' common prefix
    std::vector<std::string> candidates; // full paths, folders first then files, each sorted
    bool truncated = false;              // more than `limit` entries matched
};

// Completes the last component of `partial` within its folder (the current folder for a bare
// name). Unreadable or missing folders give no candidates; never throws.
PathCompletion complete_path(const std::string& partial, std::size_t limit = 64);

// "~/x" -> "$HOME/x"; anything else unchanged.
std::string expand_home(const std::string& path);

// True for a volume the app can try to open: an existing regular file, or a folder (DICOM).
bool openable_path(const std::string& path);

} // namespace snert::app
