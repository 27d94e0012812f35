// Sizes and memory: the checks that stand between an untrusted header and an allocation.
//
// Why snert checks what ITK already reads: ITK 5.2 zero-fills truncated NIfTI, MetaImage, VTK
// and DICOM data without an error, allocates whatever size a header claims before reading, and
// GDCM asserts (aborts) on some damaged DICOM headers. So sizes are checked against the file,
// and the grid against the memory, before ITK reads any sample. The format parsers (nifti.h,
// metaimage.h, vtk_legacy.h, nrrd.h, dicom_pixel_data.h) say what a file promises; the
// functions here refuse what does not fit. Used by the ITK loader, the raw reader and the
// libFuzzer target in tests/fuzz.
//
// Every failure is a std::runtime_error whose message starts with `name` (the file), one line.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace snert::detail {

// Largest extent snert accepts along one axis (Volume::dims is an ivec3).
inline constexpr std::uint64_t max_axis_extent = 2147483647u;

// Checks stored dims (each axis 1 .. max_axis_extent, the float32 grid's byte count does not
// overflow) and returns them as an ivec3. Throws std::runtime_error "<name>: absurd dimensions
// A x B x C (...)" otherwise.
glm::ivec3 checked_dims(const std::string& name, std::uint64_t x, std::uint64_t y, std::uint64_t z);

// MemAvailable of a /proc/meminfo text, in bytes; 0 when the line is missing or malformed.
std::uint64_t parse_meminfo_available(const std::string& meminfo);
// MemAvailable of this machine (falls back to sysconf's available pages), capped by the room
// left under a cgroup v2 memory limit, in bytes.
std::uint64_t available_memory_bytes();

// Refuses (std::runtime_error with both sizes) a grid whose float32 samples plus
// `extra_bytes` of temporary storage exceed `limit_bytes` (0: available_memory_bytes()).
void check_memory(const std::string& name, glm::ivec3 dims, std::uint64_t extra_bytes,
                  std::uint64_t limit_bytes);

// "1.5 GiB", "400.0 MiB", "12 bytes".
std::string format_bytes(std::uint64_t bytes);

// ---- What a header promises ---------------------------------------------------------------------

// Product of `factors` (a header's sizes and sample size); 0 when it overflows, which the
// callers read as "unknown": the size is then not checked, and checked_dims refuses the grid.
std::uint64_t checked_product(const std::vector<std::uint64_t>& factors);

// Absurd dimensions (checked_dims), then memory (check_memory with `memory_limit`, 0: what is
// available), for a header's axes; axes after the third fold into z.
void check_grid(const std::string& path, const std::vector<std::uint64_t>& axes,
                std::uint64_t memory_limit);

// Throws std::runtime_error "<path>: truncated <what>: the header promises <need> bytes of
// samples, <data_path, or "the file" when it is path> holds <have>".
[[noreturn]] void throw_short(const std::string& path, const std::string& what, std::uint64_t need,
                              const std::string& data_path, std::uint64_t have);

} // namespace snert::detail
