// Path completion for the Open field.
#include "path_completion.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace snert::app {

namespace fs = std::filesystem;

std::string expand_home(const std::string& path) {
    if (path == "~" || path.rfind("~/", 0) == 0) {
        if (const char* home = std::getenv("HOME"); home && *home)
            return std::string(home) + path.substr(1);
    }
    return path;
}

bool openable_path(const std::string& path) {
    std::error_code error;
    const fs::path p(expand_home(path));
    return !path.empty() && (fs::is_regular_file(p, error) || fs::is_directory(p, error));
}

PathCompletion complete_path(const std::string& partial, std::size_t limit) {
    PathCompletion result;
    result.completed = partial;
    const std::string expanded = expand_home(partial);
    // Split into the folder to list and the start of the name typed so far; the candidates
    // keep the user's own spelling of the folder ("~/", relative paths).
    const auto slash = partial.find_last_of('/');
    const std::string shown_folder = slash == std::string::npos ? "" : partial.substr(0, slash + 1);
    const std::string name_start = slash == std::string::npos ? partial : partial.substr(slash + 1);
    const auto expanded_slash = expanded.find_last_of('/');
    const fs::path folder = expanded_slash == std::string::npos
                                ? fs::path(".")
                                : fs::path(expanded.substr(0, expanded_slash + 1));
    const bool show_hidden = !name_start.empty() && name_start[0] == '.';

    std::vector<std::string> folders, files;
    std::error_code error;
    fs::directory_iterator it(folder, fs::directory_options::skip_permission_denied, error);
    if (error) return result;
    std::size_t matched = 0;
    for (; it != fs::directory_iterator(); it.increment(error)) {
        if (error) break;
        const std::string name = it->path().filename().string();
        if (name.rfind(name_start, 0) != 0) continue;
        if (!show_hidden && !name.empty() && name[0] == '.') continue;
        if (++matched > limit) {
            result.truncated = true;
            continue;
        }
        std::error_code type_error;
        if (it->is_directory(type_error))
            folders.push_back(shown_folder + name + "/");
        else
            files.push_back(shown_folder + name);
    }
    std::sort(folders.begin(), folders.end());
    std::sort(files.begin(), files.end());
    result.candidates = std::move(folders);
    result.candidates.insert(result.candidates.end(), files.begin(), files.end());
    if (result.candidates.empty()) return result;

    // The longest prefix all candidates share; it starts with `partial` by construction.
    std::string common = result.candidates.front();
    for (const std::string& c : result.candidates) {
        std::size_t n = 0;
        while (n < common.size() && n < c.size() && common[n] == c[n]) ++n;
        common.resize(n);
    }
    if (common.size() > partial.size() && !result.truncated) result.completed = common;
    return result;
}

} // namespace snert::app
