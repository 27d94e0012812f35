// VTK legacy structured points (.vtk): the header and the size check run before ITK reads the
// file (no ITK here).
//
// ITK 5.2 zero-fills a truncated VTK file without an error, so the header is parsed here and
// the samples it promises (binary bytes, or ASCII values) are counted in the file first.
//
// The parser takes a byte range and never reads outside it (tests/fuzz feeds it arbitrary
// bytes); every failure is a std::runtime_error whose message starts with `name`, one line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "sample_conversion.h"

namespace snert::detail {

struct VtkHeader {
    bool binary = false;
    std::uint64_t dims[3] = {0, 0, 0};
    std::uint64_t points = 0; // POINT_DATA
    std::string attribute;    // "SCALARS", "VECTORS", ...: the first point attribute
    std::optional<ScalarType> type;
    std::uint64_t components = 1;
    std::uint64_t data_offset = 0; // first byte of the samples of that attribute

    std::uint64_t data_bytes() const; // binary bytes promised (0: overflow or unknown type)
};
// Parses a VTK legacy header. Returns empty when the text is not a structured-points file
// snert understands (the size check is then skipped; ITK decides). Throws std::runtime_error
// when the header is recognised but inconsistent (POINT_DATA != product of DIMENSIONS).
std::optional<VtkHeader> parse_vtk_header(const std::uint8_t* bytes, std::size_t size,
                                          const std::string& name);
// Whitespace-separated tokens in bytes (ASCII VTK data), stopping once `enough` are found.
std::uint64_t count_tokens(const std::uint8_t* bytes, std::size_t size, std::uint64_t enough);

// Checks a VTK file on disk, in this order: absurd dimensions (checked_dims), memory
// (check_memory with `memory_limit`, 0: available), then the samples the header promises:
// std::runtime_error "<path>: truncated VTK: ..." when the file holds fewer bytes (binary) or
// values (ASCII). Files parse_vtk_header does not understand pass to ITK unchecked.
void check_vtk_data(const std::string& path, std::uint64_t memory_limit);

} // namespace snert::detail
