// Numbered slice series: quarter.1 .. quarter.93, IM-0001.raw .. IM-0120.raw (no ITK).
//
// The raw reader (raw_volume.h) reads a series of headerless slice files from the name of its
// first file. Pure string functions: the raw reader decides which candidate counts by looking
// at the files on disk.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace snert::detail {

// A file name with a number in it: prefix + number + suffix, e.g. "quarter." 1 "" or
// "IM-" 0001 ".raw" (width 4: zero padding is kept).
struct NumberedName {
    std::string prefix, suffix;
    std::uint64_t number = 0;
    std::size_t width = 0; // digits to pad to (0: no padding)
};
// Every run of digits in the file name (not in the folder) read as the slice number, most
// likely first: the last run before the extension ("IM-0001.raw", "s001.f64"), then the others
// from the end ("quarter.1"). The raw reader takes the first whose next number exists. Runs of
// more than 18 digits are not numbers here (number + count must stay inside uint64).
std::vector<NumberedName> numbered_name_candidates(const std::string& path);
std::optional<NumberedName> parse_numbered_name(const std::string& path); // first candidate
// The name with `number` in place of the original one, zero-padded to the original width.
std::string numbered_path(const NumberedName& name, std::uint64_t number);

} // namespace snert::detail
