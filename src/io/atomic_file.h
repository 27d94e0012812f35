// Writing files atomically: the content goes to a temporary file in the target's folder, which
// is renamed over the target only when complete. Used by every writer (meshes, JSON, PNG).
//
// The temporary file is "FOLDER/.NAME.tmp-PID-N.EXT" for a target "FOLDER/NAME.EXT" (EXT is
// everything from the first dot of the file name, kept because some producers pick the format
// from it). It is created exclusively, synced to disk (fsync) before the rename, and removed on
// every failure, so the target is either the complete new file or the untouched old one.
// Errors read "PATH: reason", the reason from strerror where the system gave one (missing
// folder, permission denied, disk full, target is a folder).
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace snert {

// Calls `write` with a binary stream to a temporary file, then renames it to `path`. Throws
// std::runtime_error naming `path` and the reason (folder missing, not writable, disk full,
// the stream left in a failed state by `write`); the temporary file is removed on failure and
// the target is left untouched. An exception thrown by `write` is passed on unchanged.
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write);

// Same, for a producer that writes to a path itself (a C library): it gets the temporary path,
// which already exists (empty) and may be overwritten. The producer reports failure by throwing
// (passed on unchanged); a producer that leaves no file or an empty one also fails, so a C
// function whose error return was ignored is still caught.
void write_path_atomically(const std::string& path,
                           const std::function<void(const std::string& temporary_path)>& write);

// Whether `path` can be written, checked before the work that produces it: its folder exists,
// is a folder and is writable (a temporary file can be created there), and `path` is not
// itself a folder. Throws std::runtime_error "PATH: reason" otherwise. Nothing is created.
void check_writable(const std::string& path);

} // namespace snert
