#include "input_file.h"

#include "input.h"

namespace snert::cli {

std::set<std::string> file_input_options() { return {}; }

void load_file_input(const std::string& path, const Args&, Input&) {
    throw std::runtime_error(path + ": reading volume files is not available in this build");
}

} // namespace snert::cli
