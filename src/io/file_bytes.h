// Files as bytes: sizes, prefixes, extensions and folders of the paths the readers are given.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace snert::detail {

// Size of a regular file; throws std::runtime_error naming it when it cannot be read.
std::uint64_t file_size(const std::string& path);
// Up to `max_bytes` from the start of a file (fewer if the file is shorter). Throws
// std::runtime_error naming the file when it cannot be opened.
std::vector<std::uint8_t> read_file_prefix(const std::string& path, std::size_t max_bytes);
// Lower-case file name extension including ".gz" pairs: ".nii.gz", ".nrrd", "" for none.
std::string volume_extension(const std::string& path);
// The folder part of `path` with its trailing '/', "" for a bare file name: a header's
// relative data file name is appended to it.
std::string folder_of(const std::string& path);

} // namespace snert::detail
