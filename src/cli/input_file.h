// Volume files as command inputs: the file-format options and the loading of a path into an
// Input (grey volume, optional label mask, suggested iso, first-order reference distance).
#pragma once

#include <set>
#include <string>

#include "args.h"

namespace snert::cli {

struct Input;

std::set<std::string> file_input_options();

// Fills input.volume, input.iso (--iso or a suggestion), input.labels and input.reference.
void load_file_input(const std::string& path, const Args& args, Input& input);

} // namespace snert::cli
