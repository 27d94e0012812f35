// Writing files atomically: the content goes to a temporary file in the target's folder, which
// is renamed over the target only when complete. Used by every writer (meshes, JSON, PNG).
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace snert {

// Calls `write` with a binary stream to a temporary file, then renames it to `path`. Throws
// std::runtime_error naming `path` and the reason (folder missing, not writable, disk full);
// the temporary file is removed on failure and the target is left untouched.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// Same, for a producer that writes to a path itself (a C library): it gets the temporary path.
void write_path_atomically(const std::string& path,
                           const std::function<void(const std::string& temporary_path)>& write);

} // namespace snert
